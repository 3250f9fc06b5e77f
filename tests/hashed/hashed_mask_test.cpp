// GeometryMask with many triangles: the builder merges its per-thread
// (cell, box) buffers while voxelising; the result must equal the union of
// masks of the same triangles taken in batches too small to merge, cell by
// cell (occupancy at every depth, and geometry boxes). Surface points lie in
// their octant's box, and octant masks reduced by those boxes keep every
// light that contains a surface point; updates derive the same reduced masks.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <functional>
#include <random>
#include <set>

#include <tbb/task_arena.h>

#include "hashed_support.hpp"
#include "host/hashed/GeometryMask.hpp"
#include "host/hashed/LightOctreeBuilder.hpp"
#include "host/hashed/OctantMask.hpp"
#include "host/hashed/OctreeBounds.hpp"
#include "host/hashed/SceneOctree.hpp"
#include "support/TestDevice.hpp"

namespace ml::hashed {
namespace {

using namespace test_support;

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
          const GeometryMask::Box* pb;
          if (!p.octantBoxes(c, pb)) continue;
          any = true;
          want.lo = glm::min(want.lo, pb->lo);
          want.hi = glm::max(want.hi, pb->hi);
        }
        const GeometryMask::Box* got = nullptr;
        ASSERT_EQ(whole.octantBoxes(c, got) != nullptr, any) << x << "," << y << "," << z;
        ASSERT_EQ(whole.has(b.depth, c), any);
        if (!any) continue;
        ++occupied;
        ASSERT_EQ(got->lo, want.lo) << x << "," << y << "," << z;
        ASSERT_EQ(got->hi, want.hi) << x << "," << y << "," << z;
        for (unsigned t = 0; t < b.depth; ++t) ASSERT_TRUE(whole.has(t, c >> (b.depth - t)));
      }
  // 8 x 16 x 16 unit cells hold triangles (the grid is larger and aligned to
  // integers); ~120 triangles each, so all of them and nothing else.
  EXPECT_EQ(occupied, 8u * 16u * 16u);
  EXPECT_EQ(whole.cellCount(), occupied);
}

// The builder counts the bytes it holds as they grow: a limit below its peak
// stops it (at about the limit, not after building), one at the peak lets
// the same mask through, and the count is not far from the buffers' size.
// One thread makes the peak repeatable (threads' buffers merge at times that
// depend on the scheduling); the threaded build must stop as well.
TEST(HashedMask, BuildStopsAtItsByteLimit) {
  const std::uint64_t seed = test::freshSeed();
  SCOPED_TRACE("seed " + std::to_string(seed));
  std::mt19937_64 rng(seed);
  const double side = 16.0;
  const OctreeBounds b = boundsForBox(glm::dvec3(0.0), glm::dvec3(side), 1.0, 0);
  const Scene s = tinyTriangles(rng, 100000 + rng() % 1000, side);
  tbb::task_arena one_thread(1);
  auto build = [&](std::size_t limit) { return one_thread.execute([&] { return GeometryMask(s, b, 0.01, limit); }); };
  const GeometryMask free_mask = build(std::size_t(-1));
  const std::size_t peak = free_mask.peakBytes();
  // At least the final cells' boxes, at most the pairs' buffers doubled.
  EXPECT_GE(peak, free_mask.cellCount() * (sizeof(GeometryMask::Box) + sizeof(GeometryMask::OctantBoxes)));
  EXPECT_LT(peak, s.indices.size() / 3 * 2 * 512);
  EXPECT_EQ(build(peak).cellCount(), free_mask.cellCount());
  auto refused = [&](std::size_t limit, bool threaded) {
    try {
      if (threaded) GeometryMask(s, b, 0.01, limit);
      else build(limit);
    } catch (const GeometryMask::OverLimit& e) {
      EXPECT_GT(e.bytes, limit);
      EXPECT_LE(e.bytes, limit + (std::size_t(8) << 20)) << "stopped when it passed the limit, not later";
      return true;
    }
    return false;
  };
  for (const std::size_t limit : {peak - 1, peak / 2, std::size_t(1) << 16})
    EXPECT_TRUE(refused(limit, false)) << "limit " << limit << " below the peak " << peak;
  EXPECT_TRUE(refused(peak / 2, true)) << "threaded, limit " << peak / 2;
}

// rowCells() and octantBoxes() answer from a dense index (depth <= 7),
// from counted bits (8 and 9) or by searching (10 and deeper): each is
// checked against the cells that hold a triangle (here each triangle lies
// well inside one cell). Rows hold many cells, some at the grid's ends.
TEST(HashedMask, RowAndCellQueriesAtEveryIndexKind) {
  const std::uint64_t seed = test::freshSeed();
  SCOPED_TRACE("seed " + std::to_string(seed));
  std::mt19937_64 rng(seed);
  for (const unsigned depth : {6u, 8u, 9u, 10u}) {
    SCOPED_TRACE("depth " + std::to_string(depth));
    const double extent = 10.0;
    const OctreeBounds b = boundsForBox(glm::dvec3(0.0), glm::dvec3(extent), extent / (0.9 * double(1u << depth)), 0);
    ASSERT_EQ(b.depth, depth);
    const unsigned n = b.cellsPerAxis();
    std::uniform_int_distribution<unsigned> any(0, n - 1), row(0, 5);
    std::uniform_real_distribution<double> in(0.3, 0.7), d(-0.05, 0.05);
    std::set<std::uint64_t> want;
    Scene s;
    for (int t = 0; t < 3000; ++t) {
      const unsigned x = t % 50 == 0 ? (t % 100 == 0 ? 0u : n - 1) : any(rng);
      const glm::uvec3 c(x, row(rng) * (n / 6), n - 1 - row(rng));  // 36 rows
      const glm::dvec3 at = glm::dvec3(c) + glm::dvec3(in(rng), in(rng), in(rng));
      glm::dvec3 v[3];
      bool inside = true;
      for (auto& p : v) {
        p = glm::dvec3(b.origin_f) + (at + glm::dvec3(d(rng), d(rng), d(rng))) / double(b.cell_scale);
        inside = inside && glm::uvec3(glm::floor(b.toCells(p))) == c;
      }
      ASSERT_TRUE(inside) << "triangle " << t << " leaves its cell";
      for (const auto& p : v) {
        s.vertices.push_back({glm::vec3(p), glm::vec3(0, 1, 0), glm::vec2(0)});
        s.indices.push_back(std::uint32_t(s.vertices.size() - 1));
      }
      want.insert(packCoord(c));
    }
    const GeometryMask mask(s, b, 0.01);
    ASSERT_EQ(mask.cellCount(), want.size());
    std::uniform_int_distribution<unsigned> wide(0, n + 4);
    for (unsigned z = n - 6; z < n; ++z)
      for (unsigned y = 0; y <= 5 * (n / 6); y += n / 6)
        for (int q = 0; q < 20; ++q) {
          unsigned lo = wide(rng), hi = wide(rng);
          if (q == 0) lo = 0, hi = n - 1;
          if (lo > hi) std::swap(lo, hi);
          std::vector<unsigned> expect, got;
          for (auto it = want.lower_bound(packCoord({lo, y, z})); it != want.end() && *it <= packCoord({std::min(hi, n - 1), y, z}); ++it)
            expect.push_back(unpackCoord(*it).x);
          const auto [first, last] = mask.rowCells(y, z, lo, hi);
          for (std::size_t i = first; i < last; ++i) {
            got.push_back(mask.cellX(i));
            const GeometryMask::Box* box = nullptr;
            ASSERT_EQ(mask.octantBoxes({mask.cellX(i), y, z}, box), &mask.cellOctants(i));
            ASSERT_EQ(box, &mask.cellBox(i));
          }
          ASSERT_EQ(got, expect) << "row y " << y << " z " << z << ", x " << lo << ".." << hi;
        }
    for (int q = 0; q < 2000; ++q) {
      const glm::uvec3 c(any(rng), q % 2 ? row(rng) * (n / 6) : any(rng), q % 3 ? n - 1 - row(rng) : any(rng));
      const GeometryMask::Box* box = nullptr;
      ASSERT_EQ(mask.octantBoxes(c, box) != nullptr, want.count(packCoord(c)) == 1) << c.x << "," << c.y << "," << c.z;
      ASSERT_EQ(mask.has(depth, c), want.count(packCoord(c)) == 1);
    }
  }
}

// 300 random triangles of up to ~3 cells in an 8-cell cube (cells of 1).
Scene randomTriangles(std::mt19937_64& rng, double side) {
  Scene s;
  std::uniform_real_distribution<double> pos(0.2, side - 0.2), d(-1.5, 1.5);
  for (int t = 0; t < 300; ++t) {
    const glm::dvec3 c(pos(rng), pos(rng), pos(rng));
    for (int k = 0; k < 3; ++k) {
      const glm::dvec3 v = glm::clamp(c + glm::dvec3(d(rng), d(rng), d(rng)), glm::dvec3(0.05), glm::dvec3(side - 0.05));
      s.vertices.push_back({glm::vec3(v), glm::vec3(0, 1, 0), glm::vec2(0)});
      s.indices.push_back(std::uint32_t(s.vertices.size() - 1));
    }
  }
  return s;
}

// A fresh seed (traced), an 8-unit octree of unit cells, random triangles
// in it and their geometry mask.
class HashedMaskGeometry : public ::testing::Test {
 protected:
  static constexpr double side = 8.0;
  const std::uint64_t seed = test::freshSeed();
  ::testing::ScopedTrace trace{__FILE__, __LINE__, "seed " + std::to_string(seed)};
  std::mt19937_64 rng{seed};
  const OctreeBounds b = boundsForBox(glm::dvec3(0.0), glm::dvec3(side), 1.0, 0);
  const Scene s = randomTriangles(rng, side);
  const GeometryMask mask{s, b, 0.01};
};

// Every point on a triangle lies in its cell's geometry box and in the box
// of the octant that holds it (what keeps octant-tight light sets conservative).
TEST_F(HashedMaskGeometry, SurfacePointsLieInTheirOctantBox) {
  std::size_t empty_octants = 0, cells = 0;
  for (int i = 0; i < 20000; ++i) {
    const glm::dvec3 p = b.toCells(randomSurfacePoint(rng, s));
    const glm::uvec3 cell(glm::floor(p));
    const GeometryMask::Box* box;
    const auto* oct = mask.octantBoxes(cell, box);
    ASSERT_NE(oct, nullptr);
    const glm::dvec3 f = p - glm::dvec3(cell);
    const unsigned k = (f.x >= 0.5 ? 1u : 0u) + (f.y >= 0.5 ? 2u : 0u) + (f.z >= 0.5 ? 4u : 0u);
    ASSERT_FALSE(oct->empty(k));
    for (int ax = 0; ax < 3; ++ax) {
      ASSERT_LE(box->lo[ax], p[ax]);
      ASSERT_GE(box->hi[ax], p[ax]);
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

// And they are tight: an octant's box lies within the union, over the
// triangles, of each triangle's bounds cut to the octant's box widened by
// the margin, widened by the margin again (plus float rounding); octants no
// triangle's bounds reach are empty. (Boxes of whole octants or cells fail.)
TEST_F(HashedMaskGeometry, OctantBoxesHoldOnlyTheTrianglesParts) {
  const double margin = 0.01 + b.eps_cells, slack = margin + 1e-5;
  const int n = int(b.cellsPerAxis());
  std::size_t octants = 0;
  for (int z = 0; z < n; ++z)
    for (int y = 0; y < n; ++y)
      for (int x = 0; x < n; ++x) {
        const GeometryMask::Box* cb = nullptr;
        const auto* oct = mask.octantBoxes(glm::uvec3(x, y, z), cb);
        if (!oct) continue;
        for (unsigned k = 0; k < 8; ++k) {
          const glm::dvec3 oc = glm::dvec3(x, y, z) + glm::dvec3(k & 1 ? 0.75 : 0.25, k & 2 ? 0.75 : 0.25, k & 4 ? 0.75 : 0.25);
          const double h = 0.25 + margin;
          glm::dvec3 ulo(1e300), uhi(-1e300);
          for (std::size_t t = 0; t + 2 < s.indices.size(); t += 3) {
            glm::dvec3 v[3];
            for (int j = 0; j < 3; ++j) v[j] = b.toCells(glm::dvec3(s.vertices[s.indices[t + std::size_t(j)]].position));
            const glm::dvec3 lo = glm::max(glm::min(v[0], glm::min(v[1], v[2])), oc - h);
            const glm::dvec3 hi = glm::min(glm::max(v[0], glm::max(v[1], v[2])), oc + h);
            if (glm::any(glm::greaterThan(lo, hi))) continue;
            ulo = glm::min(ulo, lo);
            uhi = glm::max(uhi, hi);
          }
          const std::string at = "cell " + std::to_string(x) + "," + std::to_string(y) + "," + std::to_string(z) +
                                  " octant " + std::to_string(k);
          if (ulo.x > uhi.x) {
            ASSERT_TRUE(oct->empty(k)) << at << ": no triangle reaches it";
            continue;
          }
          if (oct->empty(k)) continue;  // the separating-axis test is finer than the bounds
          ++octants;
          for (int a = 0; a < 3; ++a) {
            ASSERT_GE(double(oct->lo[k][a]), ulo[a] - slack) << at << " axis " << a;
            ASSERT_LE(double(oct->hi[k][a]), uhi[a] + slack) << at << " axis " << a;
          }
        }
      }
  EXPECT_GT(octants, 0u);
}

// Octant bits reduced by the geometry (LightOctants::onGeometry): a subset of
// the plain bits, bit k kept exactly when octant k's box (widened by eps) is
// within the radius (also through the cell box's shortcuts), and every light
// containing a surface point keeps the bit of that point's octant.
// A light octree built against the geometry mask covers exactly the cells
// with geometry whose geometry the sphere reaches (the cell's box and one
// of its octants' boxes, widened by eps, as LightOctreeBuilder states),
// no cell outside the light's cell box, and is minimal: a branch holds a
// lit cell and an unlit one (geometry unreached, or outside the box), a
// full leaf no unlit cell, an empty leaf no lit cell. Cells without
// geometry may go either way. Checked on every cell of the 8^3 octree.
TEST_F(HashedMaskGeometry, LightOctreesCoverExactlyTheCellsWhoseGeometryTheSphereReaches) {
  const auto lights = randomLights(rng, 300, side, 0.2, 3.0, true);
  const int n = int(b.cellsPerAxis());
  LightGridScratch scratch;
  std::size_t lit_cells = 0, branches = 0;
  for (std::uint32_t i = 0; i < lights.size(); ++i) {
    SCOPED_TRACE("light " + std::to_string(i));
    const auto& l = lights[i];
    const glm::dvec3 c = b.toCells(glm::dvec3(l.position_radius.x, l.position_radius.y, l.position_radius.z));
    const double r = b.radiusCells(l.position_radius.w), e = b.eps_cells;
    const CellBox box = lightCellBox(l, b);
    auto reaches = [&](const glm::dvec3& lo, const glm::dvec3& hi) {
      const glm::dvec3 d = glm::max(glm::max(lo - e - c, c - (hi + e)), glm::dvec3(0.0));
      return glm::dot(d, d) < r * r;
    };
    // Per cell: 1 lit, 0 unlit, -1 free (no geometry).
    std::vector<int> want(std::size_t(n * n * n), 0);
    for (int z = 0; z < n; ++z)
      for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x) {
          const GeometryMask::Box* cb = nullptr;
          const auto* oct = mask.octantBoxes(glm::uvec3(x, y, z), cb);
          const bool in_box = !box.empty() && glm::all(glm::greaterThanEqual(glm::ivec3(x, y, z), box.lo)) &&
                              glm::all(glm::lessThanEqual(glm::ivec3(x, y, z), box.hi));
          int& w = want[std::size_t(x + n * (y + n * z))];
          if (!oct) {
            w = in_box ? -1 : 0;
            continue;
          }
          bool lit = in_box && reaches(cb->lo, cb->hi);
          bool any = false;
          for (unsigned k = 0; k < 8 && lit; ++k)
            any = any || (!oct->empty(k) && reaches(glm::dvec3(oct->lo[k]), glm::dvec3(oct->hi[k])));
          w = lit && any ? 1 : 0;
          lit_cells += w == 1;
        }
    const LightOctree lo = buildLightOctree(l, i, b, scratch, &mask);
    // The kinds of cells in node (t, cc): bit 0 a lit cell, bit 1 an unlit one.
    auto kinds = [&](unsigned t, const glm::ivec3& cc) {
      const int size = n >> t;
      int k = 0;
      for (int z = cc.z * size; z < (cc.z + 1) * size; ++z)
        for (int y = cc.y * size; y < (cc.y + 1) * size; ++y)
          for (int x = cc.x * size; x < (cc.x + 1) * size; ++x) {
            const int w = want[std::size_t(x + n * (y + n * z))];
            k |= w == 1 ? 1 : w == 0 ? 2 : 0;
          }
      return k;
    };
    const LightNode* cur = nullptr;
    std::function<void(unsigned, glm::ivec3)> walk = [&](unsigned t, glm::ivec3 cc) {
      const LightNode type = *cur++;
      const int k = kinds(t, cc);
      const std::string at = "node depth " + std::to_string(t) + " at " + std::to_string(cc.x) + "," +
                             std::to_string(cc.y) + "," + std::to_string(cc.z);
      if (type == LightNode::Full) {
        ASSERT_EQ(k & 2, 0) << "full leaf over an unlit cell, " << at;
      }
      if (type == LightNode::Empty) {
        ASSERT_EQ(k & 1, 0) << "empty leaf over a lit cell, " << at;
      }
      if (type != LightNode::Branch) return;
      ++branches;
      ASSERT_EQ(k, 3) << "branch not holding both a lit and an unlit cell, " << at;
      for (int j = 0; j < 8; ++j) walk(t + 1, cc * 2 + glm::ivec3(j & 1, (j >> 1) & 1, (j >> 2) & 1));
    };
    int covered_lit = 0, root_lit = 0;
    for (unsigned ri = 0; ri < lo.root_count; ++ri) {
      cur = lo.nodes.data() + lo.root_start[ri];
      walk(lo.root_depth, glm::ivec3(lo.roots[ri]));
      if (HasFatalFailure()) return;
    }
    // Every lit cell lies under one of the roots (the roots hold the box).
    for (int z = 0; z < n; ++z)
      for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x) {
          if (want[std::size_t(x + n * (y + n * z))] != 1) continue;
          ++root_lit;
          for (unsigned ri = 0; ri < lo.root_count; ++ri)
            if (glm::all(glm::equal(glm::uvec3(x, y, z) >> (b.depth - lo.root_depth), lo.roots[ri]))) ++covered_lit;
        }
    ASSERT_EQ(covered_lit, root_lit) << "lit cells outside the roots";
    EXPECT_EQ(lo.filled_cells == 0, root_lit == 0);
  }
  std::printf("%zu lit cells, %zu branches over %zu lights\n", lit_cells, branches, lights.size());
  EXPECT_GT(lit_cells, 0u);
  EXPECT_GT(branches, 0u);
}

TEST_F(HashedMaskGeometry, GeometryOctantBitsKeepEveryLightOfASurfacePoint) {
  const auto lights = randomLights(rng, 200, side, 0.2, 2.5, false);
  std::size_t plain = 0, kept = 0;
  for (const auto& l : lights) {
    const LightOctants o(l, b);
    const glm::dvec3 c = b.toCells(glm::dvec3(l.position_radius.x, l.position_radius.y, l.position_radius.z));
    const CellBox box = lightCellBox(l, b);
    for (int z = box.lo.z; z <= box.hi.z; ++z)
      for (int y = box.lo.y; y <= box.hi.y; ++y)
        for (int x = box.lo.x; x <= box.hi.x; ++x) {
          const GeometryMask::Box* cell_box = nullptr;
          const auto* oct = mask.octantBoxes(glm::uvec3(x, y, z), cell_box);
          if (!oct) continue;
          const std::uint8_t m = o.mask({x, y, z}), r = o.onGeometry(m, *oct);
          ASSERT_EQ(r & ~m, 0) << "reduced bits are a subset";
          // The cell box's shortcuts give the same bits.
          ASSERT_EQ(o.onGeometry(m, *oct, *cell_box), r) << "cell " << x << "," << y << "," << z;
          ASSERT_EQ(o.onGeometry(0xFF, *oct, *cell_box), o.onGeometry(0xFF, *oct));
          for (unsigned k = 0; k < 8; ++k) {
            if (!(m >> k & 1u)) continue;
            double d2 = 0.0;
            for (int a = 0; a < 3; ++a) {
              const double lo = double(oct->lo[k][a]) - b.eps_cells, hi = double(oct->hi[k][a]) + b.eps_cells;
              const double g = c[a] < lo ? lo - c[a] : (c[a] > hi ? c[a] - hi : 0.0);
              d2 += g * g;
            }
            const bool reach = !oct->empty(k) && d2 < o.r2();
            ASSERT_EQ(bool(r >> k & 1u), reach) << "cell " << x << "," << y << "," << z << " octant " << k;
            plain += 1;
            kept += reach;
          }
        }
  }
  EXPECT_LT(kept, plain) << "the geometry clears some bits";
  EXPECT_GT(kept, 0u);
  for (int i = 0; i < 20000; ++i) {
    const glm::dvec3 p = randomSurfacePoint(rng, s);
    const glm::vec3 q = glm::vec3(b.toCells(p));
    const glm::uvec3 cell(glm::floor(q));
    const GeometryMask::Box* cell_box;
    const auto* oct = mask.octantBoxes(cell, cell_box);
    ASSERT_NE(oct, nullptr);
    for (const auto& l : lights) {
      const glm::dvec3 d = p - glm::dvec3(l.position_radius.x, l.position_radius.y, l.position_radius.z);
      if (!(glm::dot(d, d) < double(l.position_radius.w) * l.position_radius.w)) continue;
      const LightOctants o(l, b);
      const std::uint8_t r = o.onGeometry(o.mask(glm::ivec3(cell)), *oct);
      ASSERT_TRUE(r >> octantOf(q) & 1u) << "a light containing the surface point lost its octant";
    }
  }
}

// An update's octant changes with geometry (appendOctantChanges) are exactly
// the cells where the two versions' reduced masks differ, as a build derives
// each of them (its shortcuts for cells inside or outside a sphere included).
TEST_F(HashedMaskGeometry, GeometryOctantChangesEqualTheReducedMasksDifference) {
  auto reduced = [&](const gpu::PointLight* l, const glm::ivec3& cell) -> std::uint8_t {
    if (!l) return 0;
    const LightOctants o(*l, b);
    const GeometryMask::Box* cell_box;
    const auto* oct = mask.octantBoxes(glm::uvec3(cell), cell_box);
    return oct ? o.onGeometry(o.mask(cell), *oct) : o.mask(cell);
  };
  std::size_t changes = 0;
  for (int i = 0; i < 300; ++i) {
    auto pair = randomLights(rng, 2, side, 0.2, 3.0, false);
    // Mostly small moves of one light; sometimes unrelated versions, or one missing.
    if (i % 3 != 0) {
      pair[1] = pair[0];
      pair[1].position_radius.x += float(uni(rng, -0.4, 0.4));
      pair[1].position_radius.y += float(uni(rng, -0.4, 0.4));
      pair[1].position_radius.z += float(uni(rng, -0.4, 0.4));
      pair[1].position_radius.w *= float(uni(rng, 0.8, 1.2));
    }
    const gpu::PointLight* va = i % 17 == 5 ? nullptr : &pair[0];
    const gpu::PointLight* vb = i % 19 == 7 ? nullptr : &pair[1];
    std::vector<OctantChange> got;
    appendOctantChanges(va, vb, 7, b, false, &mask, got);
    std::vector<std::pair<std::uint64_t, std::uint8_t>> want, have;
    const std::int32_t n = std::int32_t(b.cellsPerAxis());
    for (int z = 0; z < n; ++z)
      for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x) {
          const std::uint8_t ma = reduced(va, {x, y, z}), mb = reduced(vb, {x, y, z});
          if (ma != mb) want.push_back({nodeKey(b.depth, glm::uvec3(x, y, z)), mb});
        }
    for (const auto& c : got) {
      ASSERT_EQ(c.light, 7u);
      have.push_back({c.key, c.mask});
    }
    std::sort(want.begin(), want.end());
    std::sort(have.begin(), have.end());
    ASSERT_EQ(have, want) << "move " << i;
    changes += have.size();
  }
  EXPECT_GT(changes, 0u);
}

}  // namespace
}  // namespace ml::hashed
