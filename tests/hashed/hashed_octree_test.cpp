// The hashed-shading structure on the host: light octrees equal the per-cell
// overlap test, and the linkless octree's lookup (the GLSL's mirror) returns
// for random points exactly the lights that overlap the point's cell, or in
// a deepest leaf with octant masks the point's octant of it: a superset of
// the lights whose sphere contains the point (conservative) and nothing
// beyond the node's reach. Also: minimal (canonical) merging, start
// depths, the geometry mask, and empty light sets.
#include <gtest/gtest.h>

#include <functional>
#include <random>

#include "hashed_support.hpp"
#include "host/hashed/LightOctreeBuilder.hpp"
#include "host/hashed/OctantMask.hpp"
#include "host/hashed/SceneOctree.hpp"
#include "host/scene/Scene.hpp"
#include "host/util/DataPaths.hpp"
#include "support/TestDevice.hpp"

namespace ml::hashed {
namespace {

using namespace test_support;

// Random access into a preorder light octree: end[i] is one past node i's subtree.
struct IndexedLightOctree {
  const LightOctree& lo;
  std::vector<std::uint32_t> end;
  explicit IndexedLightOctree(const LightOctree& o) : lo(o), end(o.nodes.size()) {
    std::function<std::uint32_t(std::uint32_t)> fill = [&](std::uint32_t i) {
      std::uint32_t j = i + 1;
      if (lo.nodes[i] == LightNode::Branch)
        for (int k = 0; k < 8; ++k) j = fill(j);
      return end[i] = j;
    };
    for (unsigned r = 0; r < o.root_count; ++r) fill(o.root_start[r]);
  }
  // Whether the light octree marks cell `c` (deepest level) as covered.
  bool covers(unsigned depth, const glm::uvec3& c) const {
    for (unsigned r = 0; r < lo.root_count; ++r) {
      if ((c >> (depth - lo.root_depth)) != lo.roots[r]) continue;
      std::uint32_t i = lo.root_start[r];
      for (unsigned t = lo.root_depth;; ++t) {
        if (lo.nodes[i] != LightNode::Branch) return lo.nodes[i] == LightNode::Full;
        const glm::uvec3 child = c >> (depth - t - 1);
        const unsigned bit = (child.x & 1u) | ((child.y & 1u) << 1) | ((child.z & 1u) << 2);
        std::uint32_t j = i + 1;
        for (unsigned k = 0; k < bit; ++k) j = end[j];
        i = j;
      }
    }
    return false;
  }
};

// 300 random lights (some huge, some tiny, some at the bounds) and their
// octree bounds at node size 0.7: the per-light octree tests' input.
struct LightSetCase {
  std::vector<gpu::PointLight> lights;
  OctreeBounds bounds;
  static LightSetCase random(std::mt19937_64& rng) {
    LightSetCase c;
    c.lights = randomLights(rng, 300, 50.0, 0.5, 6.0, true);
    HashedConfig cfg;
    cfg.node_size = "0.7";
    c.bounds = computeBounds(c.lights, cfg);
    return c;
  }
};

TEST(HashedOctree, LightOctreesMatchTheCellOverlapTest) {
  const std::uint64_t seed = test::freshSeed();
  SCOPED_TRACE("seed " + std::to_string(seed));
  std::mt19937_64 rng(seed);
  const LightSetCase lc = LightSetCase::random(rng);
  const auto& lights = lc.lights;
  const OctreeBounds& b = lc.bounds;
  LightGridScratch scratch;
  for (std::uint32_t i = 0; i < lights.size(); ++i) {
    const LightOctree lo_tree = buildLightOctree(lights[i], i, b, scratch);
    const CellBox box = lightCellBox(lights[i], b);
    const glm::dvec3 c = b.toCells({lights[i].position_radius.x, lights[i].position_radius.y, lights[i].position_radius.z});
    const double r = b.radiusCells(lights[i].position_radius.w);
    const IndexedLightOctree indexed(lo_tree);
    std::size_t filled = 0;
    const glm::ivec3 lo = box.lo - 1, ext = box.hi - box.lo + 3;
    const std::size_t cells = std::size_t(ext.x) * ext.y * ext.z;
    // The box plus a one-cell border (outside it nothing may be covered);
    // every cell of small boxes, a random sample of the huge ones.
    const bool all = cells <= 40000;
    const std::size_t probes = all ? cells : 20000;
    for (std::size_t s = 0; s < probes; ++s) {
      const std::size_t j = all ? s : std::size_t(rng() % cells);
      const glm::ivec3 cell = lo + glm::ivec3(int(j % ext.x), int((j / ext.x) % ext.y), int(j / (std::size_t(ext.x) * ext.y)));
      if (glm::any(glm::lessThan(cell, glm::ivec3(0))) || glm::any(glm::greaterThanEqual(cell, glm::ivec3(int(b.cellsPerAxis())))))
        continue;
      const bool want = sphereOverlapsCells(c, r, cell, cell, b.eps_cells);
      filled += want;
      ASSERT_EQ(indexed.covers(b.depth, glm::uvec3(cell)), want)
          << "light " << i << " cell " << cell.x << "," << cell.y << "," << cell.z;
    }
    if (all) {
      EXPECT_EQ(lo_tree.filled_cells, filled);
    }
    // Minimal: no branch whose 8 children are all full or all empty leaves.
    const LightNode* cur = lo_tree.nodes.data();
    std::function<void(unsigned)> walk = [&](unsigned t) {
      const LightNode type = *cur++;
      if (type != LightNode::Branch) return;
      const LightNode* first = cur;
      bool same = true;
      for (int k = 0; k < 8; ++k) {
        if (*cur != *first || *cur == LightNode::Branch) same = false;
        walk(t + 1);
      }
      EXPECT_FALSE(same) << "mergeable branch in light " << i;
    };
    for (unsigned r = 0; r < lo_tree.root_count; ++r) {
      cur = lo_tree.nodes.data() + lo_tree.root_start[r];
      walk(lo_tree.root_depth);
    }
    EXPECT_LE(lo_tree.root_count, 8u);
  }
}

// LightCells, the update's coverage per node without an octree, says what
// the light's octree says of every node it has (and of the 2x2x2 cells below
// each node above the cells, in one mask), and sees part of the light in
// every ancestor of a root.
TEST(HashedOctree, LightCellsAgreeWithTheLightOctree) {
  const std::uint64_t seed = test::freshSeed();
  SCOPED_TRACE("seed " + std::to_string(seed));
  std::mt19937_64 rng(seed);
  const LightSetCase lc = LightSetCase::random(rng);
  const auto& lights = lc.lights;
  const OctreeBounds& b = lc.bounds;
  LightGridScratch scratch;
  for (std::uint32_t i = 0; i < lights.size(); ++i) {
    const LightOctree o = buildLightOctree(lights[i], i, b, scratch);
    const LightCells cells(lights[i], b);
    const LightNode* cur = nullptr;
    std::function<void(unsigned, const glm::uvec3&)> walk = [&](unsigned t, const glm::uvec3& c) {
      const LightNode type = *cur++;
      ASSERT_EQ(cells.cover(t, c), type) << "light " << i << " depth " << t;
      if (t + 1 == b.depth) {
        unsigned want = type == LightNode::Full ? 0xFFu : 0u;
        for (unsigned k = 0; k < 8 && type == LightNode::Branch; ++k) want |= unsigned(cur[k] == LightNode::Full) << k;
        EXPECT_EQ(unsigned(cells.cellMask(c)), want) << "light " << i;
      }
      if (type != LightNode::Branch) return;
      for (unsigned k = 0; k < 8; ++k) walk(t + 1, childCoord(c, k));
    };
    // childCovers() is cover() of the 8 children, for every node above the
    // cells' parents: on the light, around it and far from it.
    auto expectChildCovers = [&](unsigned t, const glm::uvec3& c) {
      std::uint8_t full = 0xA5, branch = 0x5A;  // poisoned
      cells.childCovers(t, c, full, branch);
      for (unsigned k = 0; k < 8; ++k) {
        const LightNode want = cells.cover(t + 1, childCoord(c, k));
        EXPECT_EQ((full >> k) & 1u, unsigned(want == LightNode::Full)) << "light " << i << " depth " << t << " child " << k;
        EXPECT_EQ((branch >> k) & 1u, unsigned(want == LightNode::Branch)) << "light " << i << " depth " << t << " child " << k;
      }
    };
    const CellBox box = cells.box();
    const int cells_per_axis = 1 << b.depth;
    for (unsigned t = 0; t + 2 <= b.depth; ++t)
      for (int n = 0; n < 24; ++n) {
        // The node of a cell near the light's box, or anywhere one time in four.
        glm::ivec3 p;
        for (int a = 0; a < 3; ++a) {
          const bool anywhere = n % 4 == 0;
          const int lo = anywhere ? 0 : std::max(0, box.lo[a] - 2);
          const int hi = anywhere ? cells_per_axis - 1 : std::min(cells_per_axis - 1, box.hi[a] + 2);
          p[a] = lo + int(rng() % std::uint64_t(hi - lo + 1));
        }
        expectChildCovers(t, glm::uvec3(p >> int(b.depth - t)));
      }
    for (unsigned r = 0; r < o.root_count; ++r) {
      cur = o.nodes.data() + o.root_start[r];
      walk(o.root_depth, o.roots[r]);
      if (HasFailure()) return;
      for (unsigned t = 0; t < o.root_depth; ++t)
        EXPECT_NE(cells.cover(t, o.roots[r] >> (o.root_depth - t)), LightNode::Empty) << "light " << i;
    }
  }
  EXPECT_EQ(LightCells().cover(0, glm::uvec3(0)), LightNode::Empty);
  EXPECT_EQ(LightCells().cellMask(glm::uvec3(0)), 0u);
}

struct Case {
  const char* node_size;
  unsigned start_depth;
  std::size_t lights;
  bool octant_masks = true;
};

TEST(HashedOctree, LookupsListExactlyTheLightsReachingTheCellOrOctant) {
  const std::uint64_t seed = test::freshSeed();
  SCOPED_TRACE("seed " + std::to_string(seed));
  std::mt19937_64 rng(seed);
  std::size_t octant_leaves = 0;
  for (const Case& cs : {Case{"0.5r", 3, 400}, Case{"0.25r", 0, 150}, Case{"2r", 1, 400}, Case{"1.3", 20, 250},
                         Case{"0.9r", 4, 1}, Case{"0.5r", 2, 300, false}}) {
    SCOPED_TRACE(std::string(cs.node_size) + " start depth " + std::to_string(cs.start_depth) +
                 (cs.octant_masks ? "" : ", no octant masks"));
    // Relative sizes scale the median radius: "0.5r" with huge lights would be coarse,
    // so the huge ones only appear with absolute sizes.
    const bool absolute = cs.node_size[std::string(cs.node_size).size() - 1] != 'r';
    const auto lights = randomLights(rng, cs.lights, 60.0, 0.5, 4.0, absolute);
    HashedConfig cfg;
    cfg.node_size = cs.node_size;
    cfg.start_depth = cs.start_depth;
    cfg.octant_masks = cs.octant_masks;
    HashedStructure hs(cfg);
    hs.build(lights);
    const OctreeBounds& b = hs.bounds();
    EXPECT_EQ(b.start_depth, std::min(cs.start_depth, b.depth - 1));
    expectTablesPerfect(hs.linkless());
    std::size_t listed = 0, containing = 0;
    for (int i = 0; i < 3000; ++i) {
      glm::vec3 p = randomPointIn(rng, b);
      if (i % 3 == 0) {  // near a light's surface, where the cells are mixed
        const auto& l = lights[rng() % lights.size()];
        glm::dvec3 dir(uni(rng, -1, 1), uni(rng, -1, 1), uni(rng, -1, 1));
        dir = glm::normalize(dir + 1e-9);
        p = glm::vec3(glm::dvec3(l.position_radius.x, l.position_radius.y, l.position_radius.z) +
                      dir * double(l.position_radius.w) * uni(rng, 0.95, 1.05));
      }
      const auto got = hs.linkless().lightsAt(p);
      glm::uvec3 cell;
      if (!cellOf(b, p, cell)) {
        EXPECT_TRUE(got.empty());
        continue;
      }
      const auto in_cell = lightsOverlappingCell(lights, b, cell);
      // The CPU tree agrees with its hashed form.
      EXPECT_EQ(leafLightsAt(hs.tree(), cell), in_cell);
      const auto leaf = hs.tree().find(b.depth, cell);
      const bool by_octant = cs.octant_masks && leaf.exists && leaf.leaf;
      octant_leaves += by_octant && !in_cell.empty();
      const auto want = by_octant ? lightsReachingOctant(lights, b, cell, octantOf(b.cellCoordF(p))) : in_cell;
      ASSERT_EQ(got, want) << "point " << p.x << "," << p.y << "," << p.z;
      // Conservative in the plain sense: every sphere containing p is listed.
      for (std::uint32_t li = 0; li < lights.size(); ++li) {
        const auto& l = lights[li];
        const glm::dvec3 d = glm::dvec3(p) - glm::dvec3(l.position_radius.x, l.position_radius.y, l.position_radius.z);
        if (glm::dot(d, d) < double(l.position_radius.w) * l.position_radius.w) {
          ++containing;
          EXPECT_TRUE(std::binary_search(got.begin(), got.end(), li)) << "light " << li << " missing";
        }
      }
      listed += got.size();
    }
    EXPECT_GE(listed, containing);
    // Points outside the octree read as empty.
    EXPECT_EQ(hs.linkless().lookup(glm::vec3(b.origin) - glm::vec3(1.0f)).count, 0u);
    EXPECT_EQ(hs.linkless().lookup(glm::vec3(b.origin + b.side() * 1.01)).count, 0u);
    if (HasFailure()) return;
  }
  EXPECT_GT(octant_leaves, 1000u);  // the octant path was exercised
}

TEST(HashedOctree, SceneOctreeIsCanonical) {
  const std::uint64_t seed = test::freshSeed();
  SCOPED_TRACE("seed " + std::to_string(seed));
  std::mt19937_64 rng(seed);
  const auto lights = randomLights(rng, 300, 40.0, 1.0, 3.0, false);
  HashedConfig cfg;
  cfg.node_size = "0.5r";
  cfg.start_depth = 2;
  HashedStructure hs(cfg);
  hs.build(lights);
  const unsigned ds = hs.bounds().start_depth;
  // No branch below the start depth has 8 leaf children with one light set,
  // and no leaf at or above it has lights.
  std::vector<std::vector<std::uint32_t>> sets;
  hs.tree().forEachNode([&](unsigned t, const glm::uvec3& c, const SceneOctree::NodeView& v) {
    if (v.leaf) {
      if (t <= ds) {
        EXPECT_TRUE(v.lights->empty()) << "filled leaf at depth " << t;
      }
      return;
    }
    if (t <= ds || v.leaf_mask != 0xFF) return;
    const auto& first = *hs.tree().find(t + 1, childCoord(c, 0)).lights;
    bool same = true;
    for (unsigned k = 1; k < 8; ++k) same = same && *hs.tree().find(t + 1, childCoord(c, k)).lights == first;
    EXPECT_FALSE(same) << "mergeable branch at depth " << t;
  });
  // Insertion order does not matter: reversed insertion gives the same tree.
  SceneOctree rev(hs.bounds(), nullptr);
  LightGridScratch scratch;
  for (std::size_t i = lights.size(); i-- > 0;)
    rev.insert(buildLightOctree(lights[i], std::uint32_t(i), hs.bounds(), scratch));
  rev.normalize();
  const auto a = hs.tree().countsPerDepth(), b = rev.countsPerDepth();
  for (std::size_t t = 0; t < a.size(); ++t) {
    EXPECT_EQ(a[t].branches, b[t].branches) << t;
    EXPECT_EQ(a[t].filled_leaves, b[t].filled_leaves) << t;
  }
}

TEST(HashedOctree, NoLightsAndOneLight) {
  HashedConfig cfg;
  HashedStructure none(cfg);
  none.build({});
  EXPECT_EQ(none.linkless().lookup(glm::vec3(0.5f)).count, 0u);
  EXPECT_TRUE(none.linkless().pool().list().empty());
  HashedStructure one(cfg);
  one.build({makeLight({1, 2, 3}, 2.0f, glm::vec3(1))});
  EXPECT_EQ(one.linkless().lightsAt({1, 2, 3}), std::vector<std::uint32_t>{0});
  EXPECT_EQ(one.linkless().lightsAt({1, 2, 4.9f}), std::vector<std::uint32_t>{0});
  EXPECT_TRUE(one.linkless().lightsAt({1, 2, 50}).empty());
}

// With the geometry mask, points on the scene's surfaces read a subset of the
// lights listed without it that still holds every light containing the
// point (geometry-tight sets), while the structure shrinks.
TEST(HashedOctree, GeometryMaskKeepsSurfacePointsAndSavesMemory) {
  const std::uint64_t seed = test::freshSeed();
  SCOPED_TRACE("seed " + std::to_string(seed));
  std::mt19937_64 rng(seed);
  const Scene scene = loadGltfScene(dataPath("default/scene.glb"));
  const auto lights = loadLightsJson(dataPath("default/lights.json"));
  for (const char* size : {"0.5r", "0.25r"}) {
    SCOPED_TRACE(size);
    HashedConfig cfg;
    cfg.node_size = size;
    HashedStructure plain(cfg);
    plain.build(lights);
    cfg.geometry_mask = true;
    HashedStructure masked(cfg, &scene);
    masked.build(lights, plain.bounds());
    expectTablesPerfect(masked.linkless());
    EXPECT_LT(masked.linkless().gpuBytes(), plain.linkless().gpuBytes());
    EXPECT_LT(masked.tree().nodeCount(), plain.tree().nodeCount());
    std::size_t listed_masked = 0, listed_plain = 0;
    for (int i = 0; i < 4000; ++i) {
      const glm::vec3 p(randomSurfacePoint(rng, scene));
      const auto got = masked.linkless().lightsAt(p), all = plain.linkless().lightsAt(p);
      listed_masked += got.size();
      listed_plain += all.size();
      // Nothing beyond the point's cell (widened by the mask's margins).
      glm::uvec3 cell;
      ASSERT_TRUE(cellOf(masked.bounds(), p, cell));
      const auto& mb = masked.bounds();
      for (const auto li : got) {
        const auto& l = lights[li];
        ASSERT_TRUE(sphereOverlapsCells(mb.toCells({l.position_radius.x, l.position_radius.y, l.position_radius.z}),
                                        mb.radiusCells(l.position_radius.w), glm::ivec3(cell), glm::ivec3(cell), 0.2))
            << "light " << li << " listed far from its reach, point " << p.x << " " << p.y << " " << p.z;
      }
      for (std::uint32_t li = 0; li < lights.size(); ++li) {
        const auto& l = lights[li];
        const glm::dvec3 d = glm::dvec3(p) - glm::dvec3(l.position_radius.x, l.position_radius.y, l.position_radius.z);
        if (glm::dot(d, d) < double(l.position_radius.w) * l.position_radius.w) {
          ASSERT_TRUE(std::binary_search(got.begin(), got.end(), li))
              << "light " << li << " missing, point " << p.x << " " << p.y << " " << p.z;
        }
      }
    }
    EXPECT_LT(listed_masked, listed_plain) << "tight sets list fewer lights";
  }
}

}  // namespace
}  // namespace ml::hashed
