#include "host/hashed/OctreeBounds.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>

#include "host/util/Error.hpp"

namespace ml::hashed {
namespace {

glm::dvec3 pos(const gpu::PointLight& l) { return {l.position_radius.x, l.position_radius.y, l.position_radius.z}; }

std::string gib(double bytes) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.2f GiB", bytes / double(std::size_t(1) << 30));
  return buf;
}

// With a geometry mask, per light: its octree's record, the light itself and
// its share of the scene octree and of the tables: 390 bytes per light at
// 1M lights and 0.5r on the default scene (bench --scale: peak resident bytes
// by stage, the mask's own excluded); per pair of its cell box, its octree's
// node bytes (a node per cell at most, fewer where whole nodes are full or empty).
constexpr double kLightRecordBytes = 400.0;
constexpr double kMaskedOctreeBytesPerPair = 1.0;

UserError tooLarge(const std::string& node_size_text, std::size_t lights, std::size_t need, std::size_t limit) {
  return UserError("--node-size " + node_size_text + ": the octree for " + std::to_string(lights) +
                   " lights would need about " + gib(double(need)) + " (limit " + gib(double(limit)) +
                   "); use a larger node size");
}

}  // namespace

NodeSizeSpec parseNodeSize(const std::string& text) {
  NodeSizeSpec s;
  std::string num = text;
  s.relative = !num.empty() && (num.back() == 'r' || num.back() == 'R');
  if (s.relative) num.pop_back();
  double v = 0.0;
  const auto [p, ec] = std::from_chars(num.data(), num.data() + num.size(), v);
  if (num.empty() || ec != std::errc() || p != num.data() + num.size() || !std::isfinite(v))
    throw UserError("--node-size: expected a size like '2.0' or '0.5r' (times the median light radius), got '" +
                    text + "'");
  if (!(v > 0.0)) throw UserError("--node-size: must be > 0, got '" + text + "'");
  s.value = v;
  return s;
}

OctreeBounds boundsForBox(const glm::dvec3& box_min, const glm::dvec3& box_max, double node_size,
                          unsigned start_depth, const std::string& flag) {
  if (!(node_size > 0.0) || !std::isfinite(node_size))
    throw UserError(flag + ": the node size must be finite and > 0 (got " + std::to_string(node_size) + ")");
  OctreeBounds b;
  b.cell_size = node_size;
  const glm::dvec3 ext = box_max - box_min;
  const double extent = std::max({ext.x, ext.y, ext.z, 0.0});
  // The thesis's offset c against rounding: a sliver of the extent, so that
  // no sphere touches the cube's faces.
  const double c = 1e-3 * std::max(extent, node_size);
  const double needed = extent + 2.0 * c;
  const double cells = needed / node_size;
  if (!(cells <= double(1u << kMaxDepth)))
    throw UserError(flag + ": " + std::to_string(node_size) + " is too small for the lights' bounds (extent " +
                    std::to_string(extent) + " needs " + std::to_string(cells) + " cells per axis, at most " +
                    std::to_string(1u << kMaxDepth) + "); use a larger node size");
  unsigned depth = 1;
  while (double(1u << depth) < cells) ++depth;
  b.depth = depth;
  b.start_depth = std::min(start_depth, depth - 1);
  const glm::dvec3 centre = 0.5 * (box_min + box_max);
  b.origin = centre - glm::dvec3(0.5 * b.side());
  b.origin_f = glm::vec3(b.origin);
  b.cell_scale = static_cast<float>(1.0 / node_size);
  // (p - o) * s in float is off by at most ~2 ulps of a value below 2^depth.
  b.eps_cells = std::max(1e-4, std::ldexp(1.0, int(depth) - 21));
  return b;
}

OctreeBounds computeBounds(const std::vector<gpu::PointLight>& lights, const HashedConfig& config) {
  const NodeSizeSpec spec = parseNodeSize(config.node_size);
  if (lights.empty()) return boundsForBox(glm::dvec3(0.0), glm::dvec3(1.0), 1.0, 0);
  glm::dvec3 lo(1e300), hi(-1e300);
  std::vector<double> radii;
  radii.reserve(lights.size());
  for (const auto& l : lights) {
    const double r = l.position_radius.w;
    const glm::dvec3 p = pos(l);
    if (!std::isfinite(r) || !(r > 0.0) || !std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
      throw UserError("--lights: hashed shading needs finite positions and radii > 0");
    lo = glm::min(lo, p - r);
    hi = glm::max(hi, p + r);
    radii.push_back(r);
  }
  // Relative sizes scale the median radius: the typical light's. (With the
  // largest radius, a few big lights would coarsen every light's nodes; with
  // uniform radii, as in the thesis, all three choices agree.)
  const auto mid = radii.begin() + std::ptrdiff_t(radii.size() / 2);
  std::nth_element(radii.begin(), mid, radii.end());
  const double node = spec.relative ? spec.value * *mid : spec.value;
  const glm::dvec3 pad((hi - lo) * std::max(0.0, config.bounds_padding));
  OctreeBounds b = boundsForBox(lo - pad, hi + pad, node, config.start_depth);
  checkMemory(lights, b, config.memory_limit, config.node_size, config.geometry_mask);
  return b;
}

CellBox lightCellBox(const gpu::PointLight& light, const OctreeBounds& b) {
  const glm::dvec3 c = b.toCells(pos(light));
  const double r = b.radiusCells(light.position_radius.w) + b.eps_cells;
  const double n = double(b.cellsPerAxis());
  CellBox box;
  for (int a = 0; a < 3; ++a) {
    const double lo = std::floor(c[a] - r), hi = std::floor(c[a] + r);
    box.lo[a] = int(std::clamp(lo, 0.0, n - 1.0));
    box.hi[a] = int(std::clamp(hi, -1.0, n - 1.0));
    if (hi < 0.0 || lo > n - 1.0) box.hi[a] = box.lo[a] - 1;
  }
  return box;
}

bool sphereOverlapsCells(const glm::dvec3& c, double r, const glm::ivec3& lo, const glm::ivec3& hi, double eps) {
  double d2 = 0.0;
  for (int a = 0; a < 3; ++a) d2 += axisGap2(c[a], lo[a], hi[a], eps);
  return d2 < r * r;
}

bool lightsInside(const std::vector<gpu::PointLight>& lights, const OctreeBounds& b) {
  const double n = double(b.cellsPerAxis());
  for (const auto& l : lights) {
    const glm::dvec3 c = b.toCells(pos(l));
    const double r = b.radiusCells(l.position_radius.w) + 2.0 * b.eps_cells;
    for (int a = 0; a < 3; ++a)
      if (!(c[a] - r >= 0.0 && c[a] + r < n)) return false;
  }
  return true;
}

std::size_t estimateBuildBytes(const std::vector<gpu::PointLight>& lights, const OctreeBounds& b,
                               bool geometry_mask) {
  // Every byte the build holds grows with the lights' cell boxes: the leaves
  // and the light index list are bounded by their sum, per-light grids by
  // the largest. ~16 bytes per (light, cell) pair covers the index entry,
  // its share of nodes and hash entries, with room for the build's copies.
  double pairs = 0.0, largest = 0.0;
  const double r_eps = b.eps_cells;
  for (const auto& l : lights) {
    const glm::dvec3 c = b.toCells(pos(l));
    const double r = b.radiusCells(l.position_radius.w) + r_eps;
    double cells = 1.0;
    for (int a = 0; a < 3; ++a) cells *= std::floor(c[a] + r) - std::floor(c[a] - r) + 1.0;
    pairs += cells;
    largest = std::max(largest, cells);
  }
  const double per_pair = geometry_mask ? kMaskedOctreeBytesPerPair : 16.0;
  const double per_light = geometry_mask ? kLightRecordBytes : 0.0;
  const double bytes = per_pair * pairs + per_light * double(lights.size()) + 8.0 * largest + 4096.0;
  return bytes >= 1.8e19 ? std::size_t(-1) : std::size_t(bytes);
}

void checkMemory(const std::vector<gpu::PointLight>& lights, const OctreeBounds& b, std::size_t limit,
                 const std::string& node_size_text, bool geometry_mask) {
  const std::size_t need = estimateBuildBytes(lights, b, geometry_mask);
  if (need > limit) throw tooLarge(node_size_text, lights.size(), need, limit);
}

std::size_t estimateLitBytes(std::size_t lights, std::size_t lit_pairs) {
  return std::size_t(kLightRecordBytes * double(lights) + 16.0 * double(lit_pairs) + 4096.0);
}

void checkLitMemory(std::size_t lights, std::size_t lit_pairs, std::size_t limit, const std::string& node_size_text) {
  const std::size_t need = estimateLitBytes(lights, lit_pairs);
  if (need > limit) throw tooLarge(node_size_text, lights, need, limit);
}

}  // namespace ml::hashed
