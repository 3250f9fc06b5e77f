#include "host/assign/ExactLowerBound.hpp"

#include <glm/gtc/type_ptr.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <map>
#include <stdexcept>

#include "host/cl/KernelArgs.hpp"
#include "host/cl/ProgramBuilder.hpp"
#include "host/compute/HostIo.hpp"

namespace ml {

namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();

// The kernel's cell coordinate, same float operations: monotonic in x, which
// is what makes the grid conservative (a point between a light's box corners
// lands in a cell between theirs).
float cellOf(float x, float origin, float cell) { return std::floor((x - origin) / cell); }

float roundDown(double v) {
  float f = static_cast<float>(v);
  return double(f) > v ? std::nextafter(f, -kInf) : f;
}
float roundUp(double v) {
  float f = static_cast<float>(v);
  return double(f) < v ? std::nextafter(f, kInf) : f;
}

// Half the side of a light's box: |r| widened beyond what float rounding of
// the predicate can reach (relative ~3 ulp; tiny differences may flush to 0).
double halfExtent(float r) { return std::fabs(double(r)) * (1.0 + 1e-5) + 1e-18; }

bool usable(const gpu::ml_float4& s) {
  return std::isfinite(s.x) && std::isfinite(s.y) && std::isfinite(s.z) && std::isfinite(s.w) && s.w * s.w > 0.0f;
}

struct Box {
  float lo[3], hi[3];
};

Box boxOf(const gpu::ml_float4& s) {
  const double e = halfExtent(s.w);
  const double c[3] = {s.x, s.y, s.z};
  Box b{};
  for (int a = 0; a < 3; ++a) {
    b.lo[a] = roundDown(c[a] - e);
    b.hi[a] = roundUp(c[a] + e);
  }
  return b;
}

// One level: origin at the boxes' low corner, cells of `cell` (doubled until
// the dense grid fits the budget), cells listed from `first_cell` on.
gpu::BoundGridLevel levelFor(const std::vector<Box>& boxes, float cell, std::uint32_t first_cell) {
  float lo[3] = {kInf, kInf, kInf}, hi[3] = {-kInf, -kInf, -kInf};
  for (const Box& b : boxes)
    for (int a = 0; a < 3; ++a) {
      lo[a] = std::min(lo[a], b.lo[a]);
      hi[a] = std::max(hi[a], b.hi[a]);
    }
  const double budget = std::max<double>(4096.0, 8.0 * double(boxes.size()));
  for (;; cell *= 2.0f) {
    if (!std::isfinite(cell)) throw std::length_error("light grid: lights spread beyond the float range");
    double dims[3], total = 1;
    for (int a = 0; a < 3; ++a) total *= dims[a] = double(cellOf(hi[a], lo[a], cell)) + 1.0;
    if (total > budget || std::max({dims[0], dims[1], dims[2]}) >= double(1 << 23)) continue;
    gpu::BoundGridLevel g{};
    for (int a = 0; a < 3; ++a) {
      g.origin_cell[a] = lo[a];
      g.dims[a] = static_cast<std::uint32_t>(dims[a]);
    }
    g.origin_cell[3] = cell;
    g.dims[3] = first_cell;
    return g;
  }
}

// Calls f(global cell) for every cell of `g` that box `b` overlaps.
template <class F>
void forCells(const gpu::BoundGridLevel& g, const Box& b, F&& f) {
  std::uint32_t lo[3], hi[3];
  for (int a = 0; a < 3; ++a) {
    const float l = cellOf(b.lo[a], g.origin_cell[a], g.origin_cell[3]);
    const float h = cellOf(b.hi[a], g.origin_cell[a], g.origin_cell[3]);
    lo[a] = static_cast<std::uint32_t>(std::clamp(l, 0.0f, float(g.dims[a] - 1)));
    hi[a] = static_cast<std::uint32_t>(std::clamp(h, 0.0f, float(g.dims[a] - 1)));
  }
  for (std::uint32_t z = lo[2]; z <= hi[2]; ++z)
    for (std::uint32_t y = lo[1]; y <= hi[1]; ++y)
      for (std::uint32_t x = lo[0]; x <= hi[0]; ++x) f(g.dims[3] + x + g.dims[0] * (y + g.dims[1] * z));
}

// Column-major 4x4 times (x, y, z, w), summed column by column like GLSL.
void matMul(const float* m, const float v[4], float out[4]) {
  for (int r = 0; r < 4; ++r) out[r] = m[r] * v[0] + m[4 + r] * v[1] + m[8 + r] * v[2] + m[12 + r] * v[3];
}

}  // namespace

LightGrid buildLightGrid(const std::vector<gpu::PointLight>& lights) {
  LightGrid grid;
  grid.spheres.reserve(lights.size());
  double smallest = std::numeric_limits<double>::infinity();
  for (const auto& l : lights) {
    grid.spheres.push_back(l.position_radius);
    if (usable(l.position_radius)) smallest = std::min(smallest, halfExtent(l.position_radius.w));
  }
  // Bands of half extents [smallest * 2^k, smallest * 2^(k+1)), cells of twice
  // the band's low end: a box spans at most 3 cells per axis.
  std::map<int, std::vector<std::uint32_t>> bands;
  for (std::uint32_t i = 0; i < lights.size(); ++i) {
    const auto& s = lights[i].position_radius;
    if (!usable(s)) continue;
    bands[std::max(0, static_cast<int>(std::floor(std::log2(halfExtent(s.w) / smallest))))].push_back(i);
  }
  std::vector<std::vector<Box>> boxes;
  std::size_t cells = 0;
  for (const auto& [band, members] : bands) {
    auto& bx = boxes.emplace_back();
    for (std::uint32_t i : members) bx.push_back(boxOf(lights[i].position_radius));
    const float cell = static_cast<float>(std::ldexp(smallest, band + 1));
    grid.levels.push_back(levelFor(bx, cell, static_cast<std::uint32_t>(cells)));
    const auto& g = grid.levels.back();
    cells += std::size_t(g.dims[0]) * g.dims[1] * g.dims[2];
    if (cells >= std::numeric_limits<std::uint32_t>::max()) throw std::length_error("light grid: too many cells");
  }
  // Count, scan, fill.
  std::vector<std::uint64_t> start(cells + 1, 0);
  std::size_t li = 0;
  for (const auto& bx : boxes) {
    for (const Box& b : bx) forCells(grid.levels[li], b, [&](std::uint32_t c) { ++start[c + 1]; });
    ++li;
  }
  for (std::size_t c = 0; c < cells; ++c) start[c + 1] += start[c];
  if (start[cells] > std::numeric_limits<std::uint32_t>::max()) throw std::length_error("light grid: too many entries");
  grid.cell_start.assign(start.begin(), start.end());
  grid.entries.resize(start[cells]);
  li = 0;
  for (const auto& band : bands) {
    const auto& members = band.second;  // a named reference: clang 14 cannot capture a structured binding
    for (std::size_t k = 0; k < members.size(); ++k)
      forCells(grid.levels[li], boxes[li][k], [&](std::uint32_t c) { grid.entries[start[c]++] = members[k]; });
    ++li;
  }
  return grid;
}

gpu::BoundParams boundParams(const glm::mat4& view, const glm::mat4& proj, unsigned width, unsigned height) {
  gpu::BoundParams p{};
  // The same inverses the shaders get (FrameRenderer::setFrameUniforms).
  const glm::mat4 inv_view = glm::inverse(view);
  std::memcpy(p.inv_view, glm::value_ptr(inv_view), sizeof p.inv_view);
  std::memcpy(p.proj, glm::value_ptr(proj), sizeof p.proj);
  p.width = width;
  p.height = height;
  return p;
}

bool windowToWorld(float depth, unsigned x, unsigned y, const gpu::BoundParams& p, glm::vec3& world) {
  if (gpu::is_sky_depth(depth)) return false;
  const float z = gpu::depth_to_distance(depth, p.proj[10], p.proj[14]);
  const float ndc_x = (float(x) + 0.5f) / float(p.width) * 2.0f - 1.0f;
  const float ndc_y = (float(y) + 0.5f) / float(p.height) * 2.0f - 1.0f;
  const float vx = (ndc_x + p.proj[8]) / p.proj[0];
  const float vy = (ndc_y + p.proj[9]) / p.proj[5];
  const float view[4] = {z * vx, z * vy, -z, 1.0f};
  float w[4];
  matMul(p.inv_view, view, w);
  world = {w[0], w[1], w[2]};
  return true;
}

std::uint32_t boundAtPixel(const LightGrid& grid, const gpu::BoundParams& p, float depth, unsigned x, unsigned y) {
  glm::vec3 P;
  if (!windowToWorld(depth, x, y, p, P)) return 0;
  std::uint32_t n = 0;
  for (const auto& g : grid.levels) {
    const float s = g.origin_cell[3];
    const float q[3] = {std::floor((P.x - g.origin_cell[0]) / s), std::floor((P.y - g.origin_cell[1]) / s),
                        std::floor((P.z - g.origin_cell[2]) / s)};
    if (!(q[0] >= 0.0f && q[0] < float(g.dims[0]) && q[1] >= 0.0f && q[1] < float(g.dims[1]) && q[2] >= 0.0f &&
          q[2] < float(g.dims[2])))
      continue;
    const std::uint32_t c = g.dims[3] + std::uint32_t(q[0]) + g.dims[0] * (std::uint32_t(q[1]) + g.dims[1] * std::uint32_t(q[2]));
    for (std::uint32_t e = grid.cell_start[c]; e < grid.cell_start[c + 1]; ++e) {
      const auto& L = grid.spheres[grid.entries[e]];
      const float dx = L.x - P.x, dy = L.y - P.y, dz = L.z - P.z;
      const float d2 = dx * dx + dy * dy + dz * dz;
      if (d2 < L.w * L.w) ++n;
    }
  }
  return n;
}

ExactLowerBound::ExactLowerBound(ClRuntime& rt) : rt_(rt) {
  program_ = rt.programs().build("assign/exact_lower_bound.cl");
  kernel_ = cl::Kernel(program_, "exact_lower_bound");
  params_ = cl::Buffer(rt.context(), CL_MEM_READ_ONLY, sizeof(gpu::BoundParams));
}

void ExactLowerBound::setLights(cl::CommandQueue& q, const std::vector<gpu::PointLight>& lights) {
  grid_ = buildLightGrid(lights);
  longest_list_ = 0;
  for (std::size_t c = 0; c + 1 < grid_.cell_start.size(); ++c)
    longest_list_ = std::max(longest_list_, grid_.cell_start[c + 1] - grid_.cell_start[c]);
  const auto& ctx = rt_.context();
  levels_ = compute::upload(ctx, q, grid_.levels);
  cell_start_ = compute::upload(ctx, q, grid_.cell_start);
  entries_ = compute::upload(ctx, q, grid_.entries);
  spheres_ = compute::upload(ctx, q, grid_.spheres);
}

void ExactLowerBound::count(cl::CommandQueue& q, const cl::Buffer& depth, gpu::BoundParams p, cl::Buffer& counts,
                            ClPassTimer* timer) {
  p.level_count = static_cast<std::uint32_t>(grid_.levels.size());
  q.enqueueWriteBuffer(params_, CL_TRUE, 0, sizeof p, &p);
  const std::size_t n = std::size_t(p.width) * p.height;
  if (n == 0) return;
  // Slices of every cell's list, so that no work-item loops more than
  // kLoopCap times in all (the kernel's header says why).
  const std::uint32_t levels = std::max<std::uint32_t>(1, p.level_count);
  const std::uint32_t span = std::max<std::uint32_t>(1, kLoopCap / levels - 1);
  std::uint32_t first = 0;
  do {
    setArgs(kernel_, depth, params_, levels_, cell_start_, entries_, spheres_, counts, first, span);
    q.enqueueNDRangeKernel(kernel_, cl::NullRange, cl::NDRange(n), cl::NullRange, nullptr,
                           timer ? timer->next("lower-bound") : nullptr);
    first += span;
  } while (first < longest_list_);
}

}  // namespace ml
