// GeometryMask with many triangles: the builder merges its per-thread
// (cell, box) buffers while voxelising; the result must equal the union of
// masks of the same triangles taken in batches too small to merge, cell by
// cell (occupancy at every depth, and geometry boxes).
#include <gtest/gtest.h>

#include <random>

#include "host/hashed/GeometryMask.hpp"
#include "host/hashed/OctreeBounds.hpp"
#include "support/TestDevice.hpp"

namespace ml::hashed {
namespace {

Scene tinyTriangles(std::mt19937_64& rng, std::size_t count, double side) {
  Scene s;
  // Only the lower half in x holds triangles: the other half stays empty.
  std::uniform_real_distribution<double> cell(0.0, side), half(0.0, side / 2), in(0.1, 0.9), d(-0.04, 0.04);
  for (std::size_t t = 0; t < count; ++t) {
    const glm::dvec3 c(std::floor(half(rng)) + in(rng), std::floor(cell(rng)) + in(rng), std::floor(cell(rng)) + in(rng));
    for (int k = 0; k < 3; ++k) {
      s.vertices.push_back({glm::vec3(c + glm::dvec3(d(rng), d(rng), d(rng))), glm::vec3(0, 1, 0), glm::vec2(0)});
      s.indices.push_back(std::uint32_t(s.vertices.size() - 1));
    }
  }
  return s;
}

TEST(HashedMask, MergingBuffersMatchesBatchedUnion) {
  const std::uint64_t seed = test::freshSeed();
  SCOPED_TRACE("seed " + std::to_string(seed));
  std::mt19937_64 rng(seed);
  const double side = 16.0;
  const OctreeBounds b = boundsForBox(glm::dvec3(0.0), glm::dvec3(side), 1.0, 0);
  // 5 batches of 50k triangles (one cell each, far from cell borders): each
  // batch stays below the merge threshold, all of them together do not.
  const std::size_t batch = 50000, batches = 5;
  const Scene all = tinyTriangles(rng, batch * batches, side);
  const GeometryMask whole(all, b, 0.01);
  std::vector<GeometryMask> parts;
  for (std::size_t i = 0; i < batches; ++i) {
    Scene part;
    part.vertices.assign(all.vertices.begin() + std::ptrdiff_t(3 * batch * i),
                         all.vertices.begin() + std::ptrdiff_t(3 * batch * (i + 1)));
    for (std::uint32_t k = 0; k < 3 * batch; ++k) part.indices.push_back(k);
    parts.emplace_back(part, b, 0.01);
  }
  const unsigned n = b.cellsPerAxis();
  std::size_t occupied = 0;
  for (unsigned z = 0; z < n; ++z)
    for (unsigned y = 0; y < n; ++y)
      for (unsigned x = 0; x < n; ++x) {
        const glm::uvec3 c(x, y, z);
        bool any = false;
        GeometryMask::Box want{glm::dvec3(1e300), glm::dvec3(-1e300)};
        for (const auto& p : parts) {
          GeometryMask::Box pb;
          if (!p.geometryBox(c, pb)) continue;
          any = true;
          want.lo = glm::min(want.lo, pb.lo);
          want.hi = glm::max(want.hi, pb.hi);
        }
        GeometryMask::Box got;
        ASSERT_EQ(whole.geometryBox(c, got), any) << x << "," << y << "," << z;
        ASSERT_EQ(whole.has(b.depth, c), any);
        if (!any) continue;
        ++occupied;
        ASSERT_EQ(got.lo, want.lo) << x << "," << y << "," << z;
        ASSERT_EQ(got.hi, want.hi) << x << "," << y << "," << z;
        for (unsigned t = 0; t < b.depth; ++t) ASSERT_TRUE(whole.has(t, c >> (b.depth - t)));
      }
  // 8 x 16 x 16 unit cells hold triangles (the grid is larger and aligned to
  // integers); ~120 triangles each, so all of them and nothing else.
  EXPECT_EQ(occupied, 8u * 16u * 16u);
  EXPECT_EQ(whole.cellCount(), occupied);
}

// Every point on a triangle lies in its cell's geometry box and in the box
// of the octant that holds it (what keeps octant-tight light sets conservative).
TEST(HashedMask, SurfacePointsLieInTheirOctantBox) {
  const std::uint64_t seed = test::freshSeed();
  SCOPED_TRACE("seed " + std::to_string(seed));
  std::mt19937_64 rng(seed);
  const double side = 8.0;
  const OctreeBounds b = boundsForBox(glm::dvec3(0.0), glm::dvec3(side), 1.0, 0);
  Scene s;
  std::uniform_real_distribution<double> pos(0.2, side - 0.2), d(-1.5, 1.5), u01(0.0, 1.0);
  for (int t = 0; t < 300; ++t) {
    const glm::dvec3 c(pos(rng), pos(rng), pos(rng));
    for (int k = 0; k < 3; ++k) {
      const glm::dvec3 v = glm::clamp(c + glm::dvec3(d(rng), d(rng), d(rng)), glm::dvec3(0.05), glm::dvec3(side - 0.05));
      s.vertices.push_back({glm::vec3(v), glm::vec3(0, 1, 0), glm::vec2(0)});
      s.indices.push_back(std::uint32_t(s.vertices.size() - 1));
    }
  }
  const GeometryMask mask(s, b, 0.01);
  std::size_t empty_octants = 0, cells = 0;
  for (int i = 0; i < 20000; ++i) {
    const std::size_t t = rng() % 300;
    double u = u01(rng), v = u01(rng);
    if (u + v > 1) u = 1 - u, v = 1 - v;
    const glm::dvec3 a(s.vertices[3 * t].position), p1(s.vertices[3 * t + 1].position), p2(s.vertices[3 * t + 2].position);
    const glm::dvec3 p = b.toCells(a + u * (p1 - a) + v * (p2 - a));
    const glm::uvec3 cell(glm::floor(p));
    GeometryMask::Box box;
    ASSERT_TRUE(mask.geometryBox(cell, box));
    const auto* oct = mask.octantBoxes(cell);
    ASSERT_NE(oct, nullptr);
    const glm::dvec3 f = p - glm::dvec3(cell);
    const unsigned k = (f.x >= 0.5 ? 1u : 0u) + (f.y >= 0.5 ? 2u : 0u) + (f.z >= 0.5 ? 4u : 0u);
    ASSERT_FALSE(oct->empty(k));
    for (int ax = 0; ax < 3; ++ax) {
      ASSERT_LE(box.lo[ax], p[ax]);
      ASSERT_GE(box.hi[ax], p[ax]);
      ASSERT_LE(double(oct->lo[k][ax]), p[ax]) << "octant " << k;
      ASSERT_GE(double(oct->hi[k][ax]), p[ax]) << "octant " << k;
    }
    if (i < 2000) {
      ++cells;
      for (unsigned j = 0; j < 8; ++j) empty_octants += oct->empty(j);
    }
  }
  EXPECT_GT(empty_octants, 0u) << "octants refine some cells (of " << cells << ")";
}

}  // namespace
}  // namespace ml::hashed
