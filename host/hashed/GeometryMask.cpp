#include "host/hashed/GeometryMask.hpp"

#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <chrono>
#include <cmath>

namespace ml::hashed {
namespace {

constexpr unsigned kDenseMaxDepth = 8;  // 8^8 bits = 2 MiB

// Akenine-Moller's separating-axis test of a triangle against the box
// centred at the origin with half size h (same on every axis).
bool triangleBoxOverlap(glm::dvec3 v0, glm::dvec3 v1, glm::dvec3 v2, double h) {
  const glm::dvec3 e[3] = {v1 - v0, v2 - v1, v0 - v2};
  const glm::dvec3 v[3] = {v0, v1, v2};
  // 9 edge x box-axis directions.
  for (int i = 0; i < 3; ++i)
    for (int a = 0; a < 3; ++a) {
      glm::dvec3 axis(0.0);
      axis[a] = 1.0;
      const glm::dvec3 n = glm::cross(axis, e[i]);
      const double p0 = glm::dot(n, v[0]), p1 = glm::dot(n, v[1]), p2 = glm::dot(n, v[2]);
      const double rad = h * (std::fabs(n.x) + std::fabs(n.y) + std::fabs(n.z));
      if (std::min({p0, p1, p2}) > rad || std::max({p0, p1, p2}) < -rad) return false;
    }
  // Box axes.
  for (int a = 0; a < 3; ++a)
    if (std::min({v0[a], v1[a], v2[a]}) > h || std::max({v0[a], v1[a], v2[a]}) < -h) return false;
  // Triangle plane.
  const glm::dvec3 n = glm::cross(e[0], e[1]);
  const double d = glm::dot(n, v0);
  const double rad = h * (std::fabs(n.x) + std::fabs(n.y) + std::fabs(n.z));
  return std::fabs(d) <= rad;
}

}  // namespace

GeometryMask GeometryMask::everywhere(const OctreeBounds& b) {
  GeometryMask m(b);
  m.everywhere_ = true;
  m.cell_count_ = std::size_t(b.cellsPerAxis()) * b.cellsPerAxis() * b.cellsPerAxis();
  return m;
}

GeometryMask::GeometryMask(const Scene& scene, const OctreeBounds& b, double margin_cells) : depth_(b.depth) {
  const auto t0 = std::chrono::steady_clock::now();
  const double n = double(b.cellsPerAxis());
  const double margin = std::max(margin_cells, 0.0) + b.eps_cells;
  tbb::enumerable_thread_specific<std::vector<std::uint64_t>> local;
  const std::size_t tris = scene.indices.size() / 3;
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, tris, 256), [&](const auto& range) {
    auto& out = local.local();
    for (std::size_t t = range.begin(); t != range.end(); ++t) {
      glm::dvec3 v[3];
      for (int k = 0; k < 3; ++k) v[k] = b.toCells(glm::dvec3(scene.vertices[scene.indices[3 * t + k]].position));
      const glm::dvec3 lo = glm::min(v[0], glm::min(v[1], v[2])) - margin;
      const glm::dvec3 hi = glm::max(v[0], glm::max(v[1], v[2])) + margin;
      if (hi.x < 0 || hi.y < 0 || hi.z < 0 || lo.x >= n || lo.y >= n || lo.z >= n) continue;
      const glm::ivec3 clo(glm::clamp(glm::floor(lo), glm::dvec3(0.0), glm::dvec3(n - 1)));
      const glm::ivec3 chi(glm::clamp(glm::floor(hi), glm::dvec3(0.0), glm::dvec3(n - 1)));
      for (int z = clo.z; z <= chi.z; ++z)
        for (int y = clo.y; y <= chi.y; ++y)
          for (int x = clo.x; x <= chi.x; ++x) {
            const glm::dvec3 centre(x + 0.5, y + 0.5, z + 0.5);
            if (triangleBoxOverlap(v[0] - centre, v[1] - centre, v[2] - centre, 0.5 + margin))
              out.push_back(packCoord(glm::uvec3(x, y, z)));
          }
    }
  });
  std::vector<std::uint64_t> keys;
  for (auto& l : local) keys.insert(keys.end(), l.begin(), l.end());
  setCells(std::move(keys));
  build_ms_ = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

void GeometryMask::setCells(std::vector<std::uint64_t> keys) {
  std::sort(keys.begin(), keys.end());
  keys.erase(std::unique(keys.begin(), keys.end()), keys.end());
  cell_count_ = keys.size();
  dense_.assign(depth_ + 1, {});
  sparse_.assign(depth_ + 1, {});
  for (int t = int(depth_); t >= 0; --t) {
    if (t < int(depth_)) {
      // Parents of the deeper level's nodes.
      std::vector<std::uint64_t> up;
      up.reserve(keys.size() / 4 + 1);
      for (auto k : keys) up.push_back(packCoord(unpackCoord(k) >> 1u));
      std::sort(up.begin(), up.end());
      up.erase(std::unique(up.begin(), up.end()), up.end());
      keys = std::move(up);
    }
    if (unsigned(t) <= kDenseMaxDepth) {
      const std::uint64_t side = std::uint64_t(1) << t;
      auto& bits = dense_[t];
      bits.assign((side * side * side + 63) / 64, 0);
      for (auto k : keys) {
        const glm::uvec3 c = unpackCoord(k);
        const std::uint64_t i = c.x + side * (c.y + side * c.z);
        bits[i >> 6] |= std::uint64_t(1) << (i & 63);
      }
    }
    if (unsigned(t) > kDenseMaxDepth) sparse_[t] = keys;
  }
}

bool GeometryMask::has(unsigned t, const glm::uvec3& c) const {
  if (everywhere_) return true;
  const std::uint64_t side = std::uint64_t(1) << t;
  if (c.x >= side || c.y >= side || c.z >= side) return false;
  if (t <= kDenseMaxDepth) {
    const std::uint64_t i = c.x + side * (c.y + side * c.z);
    return (dense_[t][i >> 6] >> (i & 63)) & 1u;
  }
  const auto& v = sparse_[t];
  return std::binary_search(v.begin(), v.end(), packCoord(c));
}

std::size_t GeometryMask::memoryBytes() const {
  std::size_t s = 0;
  for (const auto& d : dense_) s += d.size() * 8;
  for (const auto& d : sparse_) s += d.size() * 8;
  return s;
}

}  // namespace ml::hashed
