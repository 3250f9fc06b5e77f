#pragma once
// Shared helpers of the hashed-shading tests: random light sets (including
// huge lights and lights touching the bounds), random points, the per-cell
// reference light sets and table checks.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <vector>

#include "host/hashed/HashedStructure.hpp"
#include "host/scene/LightSet.hpp"

namespace ml::hashed::test_support {

inline double uni(std::mt19937_64& rng, double a, double b) {
  return a + (b - a) * double(rng() >> 11) * 0x1.0p-53;
}

// A uniform random point on a random triangle of `s`.
inline glm::dvec3 randomSurfacePoint(std::mt19937_64& rng, const Scene& s) {
  const std::size_t t = rng() % (s.indices.size() / 3);
  double u = uni(rng, 0, 1), v = uni(rng, 0, 1);
  if (u + v > 1) u = 1 - u, v = 1 - v;
  const glm::dvec3 a(s.vertices[s.indices[3 * t]].position), p1(s.vertices[s.indices[3 * t + 1]].position),
      p2(s.vertices[s.indices[3 * t + 2]].position);
  return a + u * (p1 - a) + v * (p2 - a);
}

// n lights in [0, size]^3 with radii in [rmin, rmax]; some huge ones and some
// whose spheres reach the box's faces when `extremes`.
inline std::vector<gpu::PointLight> randomLights(std::mt19937_64& rng, std::size_t n, double size, double rmin,
                                                 double rmax, bool extremes) {
  std::vector<gpu::PointLight> out;
  for (std::size_t i = 0; i < n; ++i) {
    glm::vec3 p(uni(rng, 0, size), uni(rng, 0, size), uni(rng, 0, size));
    double r = uni(rng, rmin, rmax);
    if (extremes && i % 17 == 3) r = size * uni(rng, 0.3, 0.9);  // covers much of the scene
    if (extremes && i % 13 == 5) r = rmin * 0.05;                // much smaller than a cell
    if (extremes && i % 11 == 7) p[int(rng() % 3)] = (rng() & 1) ? 0.0f : float(size);  // at the bounds
    out.push_back(makeLight(p, float(r), glm::vec3(1.0f)));
  }
  return out;
}

// Lights the lookup must list at cell `c`: exactly those the builder's
// overlap predicate accepts (the canonical octree is exact per cell).
inline std::vector<std::uint32_t> lightsOverlappingCell(const std::vector<gpu::PointLight>& lights,
                                                        const OctreeBounds& b, const glm::uvec3& c) {
  std::vector<std::uint32_t> out;
  for (std::uint32_t i = 0; i < lights.size(); ++i) {
    const auto& l = lights[i];
    const glm::dvec3 lc = b.toCells({l.position_radius.x, l.position_radius.y, l.position_radius.z});
    if (sphereOverlapsCells(lc, b.radiusCells(l.position_radius.w), glm::ivec3(c), glm::ivec3(c), b.eps_cells))
      out.push_back(i);
  }
  return out;
}

// Of those, the ones whose sphere reaches octant `k` (x + 2y + 4z) of the
// cell, i.e. its half-size sub-cell widened by eps: what a deepest leaf's
// octant masks let through (reference: the clamped closest point).
inline std::vector<std::uint32_t> lightsReachingOctant(const std::vector<gpu::PointLight>& lights,
                                                       const OctreeBounds& b, const glm::uvec3& c, unsigned k) {
  const glm::dvec3 lo = glm::dvec3(c) + 0.5 * glm::dvec3(k & 1u, (k >> 1) & 1u, (k >> 2) & 1u) - b.eps_cells;
  const glm::dvec3 hi = lo + 0.5 + 2.0 * b.eps_cells;
  std::vector<std::uint32_t> out;
  for (const auto i : lightsOverlappingCell(lights, b, c)) {
    const auto& l = lights[i];
    const glm::dvec3 lc = b.toCells({l.position_radius.x, l.position_radius.y, l.position_radius.z});
    const glm::dvec3 d = glm::clamp(lc, lo, hi) - lc;
    const double r = b.radiusCells(l.position_radius.w);
    if (glm::dot(d, d) < r * r) out.push_back(i);
  }
  return out;
}

inline glm::vec3 randomPointIn(std::mt19937_64& rng, const OctreeBounds& b) {
  const double s = b.side();
  return glm::vec3(b.origin + glm::dvec3(uni(rng, 0, s), uni(rng, 0, s), uni(rng, 0, s)));
}

inline bool cellOf(const OctreeBounds& b, const glm::vec3& p, glm::uvec3& cell) {
  const glm::vec3 q = b.cellCoordF(p);
  const float n = float(b.cellsPerAxis());
  if (!(q.x >= 0 && q.y >= 0 && q.z >= 0 && q.x < n && q.y < n && q.z < n)) return false;
  cell = glm::min(glm::uvec3(q), glm::uvec3(b.cellsPerAxis() - 1));
  return true;
}

// The light set of the leaf of `tree` that holds deepest cell `c`.
inline std::vector<std::uint32_t> leafLightsAt(const SceneOctree& tree, const glm::uvec3& c) {
  const unsigned depth = tree.bounds().depth;
  for (unsigned t = 0; t <= depth; ++t) {
    const SceneOctree::NodeView v = tree.find(t, c >> (depth - t));
    if (v.exists && v.leaf) return *v.lights;
  }
  return {};
}

// Every table of the linkless octree is perfect and reads back its keys.
inline void expectTablesPerfect(const LinklessOctree& lo) {
  for (unsigned i = 0; i < lo.layerCount(); ++i) {
    auto check = [&](const auto& h) {
      const auto entries = h.entries();
      for (const auto& e : entries) {
        const auto got = h.lookup(e.key);
        ASSERT_TRUE(got.has_value());
        EXPECT_TRUE(*got == e.payload);
      }
      EXPECT_EQ(entries.size(), h.size());
    };
    check(lo.desc(i));
    check(lo.data(i));
  }
}

}  // namespace ml::hashed::test_support
