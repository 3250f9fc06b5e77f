// The full build with the geometry mask (the renderer's default) on one
// thread and on eight (tbb::global_control, more threads than cores so that
// the parallel stages split and interleave differently): the same light
// octrees, the same scene octree node for node, and the same light index
// list, hash tables and GPU image word for word. Also: the geometry mask's
// row lookup, which the light octrees use, lists exactly the cells that the
// per-cell lookup finds.
#include <gtest/gtest.h>
#include <tbb/global_control.h>
#include <tbb/task_arena.h>

#include <random>

#include "hashed_support.hpp"
#include "host/hashed/GeometryMask.hpp"
#include "support/TestDevice.hpp"

namespace ml::hashed {
namespace {

using namespace test_support;

constexpr double kBox = 40.0;

// Triangles of up to a few units scattered through the box, plus a floor:
// geometry in many cells of every subtree.
Scene scatteredTriangles(std::mt19937_64& rng, std::size_t count) {
  Scene s;
  auto add = [&](const glm::dvec3& v) {
    s.vertices.push_back({glm::vec3(v), glm::vec3(0, 1, 0), glm::vec2(0)});
    s.indices.push_back(std::uint32_t(s.vertices.size() - 1));
  };
  for (std::size_t t = 0; t < count; ++t) {
    const glm::dvec3 c(uni(rng, 1, kBox - 1), uni(rng, 1, kBox - 1), uni(rng, 1, kBox - 1));
    for (int k = 0; k < 3; ++k) add(c + glm::dvec3(uni(rng, -2, 2), uni(rng, -2, 2), uni(rng, -2, 2)));
  }
  for (const glm::dvec3& v : {glm::dvec3(0, 0.5, 0), glm::dvec3(kBox, 0.5, 0), glm::dvec3(0, 0.5, kBox),
                              glm::dvec3(kBox, 0.5, 0), glm::dvec3(kBox, 0.5, kBox), glm::dvec3(0, 0.5, kBox)})
    add(v);
  return s;
}

struct Built {
  std::vector<LightOctree> octrees;
  std::unique_ptr<HashedStructure> hs;
};

Built buildAll(const std::vector<gpu::PointLight>& lights, const HashedConfig& cfg, const Scene& scene) {
  Built out;
  out.hs = std::make_unique<HashedStructure>(cfg, &scene);
  out.hs->build(lights);
  out.octrees = out.hs->lightOctrees();
  return out;
}

// Every node of the scene octree in preorder: depth, coordinate, kind, set.
std::vector<std::uint64_t> treeWords(const SceneOctree& tree) {
  std::vector<std::uint64_t> w;
  tree.forEachNode([&](unsigned t, const glm::uvec3& c, const SceneOctree::NodeView& v) {
    w.push_back(nodeKey(t, c));
    w.push_back(v.leaf ? 1 + v.lights->size() : 0x100u * v.leaf_mask + v.filled_mask);
    if (v.leaf) w.insert(w.end(), v.lights->begin(), v.lights->end());
  });
  return w;
}

void expectSameOctrees(const std::vector<LightOctree>& x, const std::vector<LightOctree>& y) {
  ASSERT_EQ(x.size(), y.size());
  for (std::size_t i = 0; i < x.size(); ++i) {
    ASSERT_EQ(x[i].root_depth, y[i].root_depth) << "light " << i;
    ASSERT_EQ(x[i].root_count, y[i].root_count) << "light " << i;
    EXPECT_EQ(x[i].filled_cells, y[i].filled_cells) << "light " << i;
    for (unsigned r = 0; r < x[i].root_count; ++r) {
      EXPECT_EQ(x[i].roots[r], y[i].roots[r]) << "light " << i;
      EXPECT_EQ(x[i].root_start[r], y[i].root_start[r]) << "light " << i;
    }
    ASSERT_EQ(x[i].nodes, y[i].nodes) << "light " << i;
  }
}

TEST(HashedBuildThreads, FullBuildDoesNotDependOnTheThreadCount) {
  const std::uint64_t seed = test::freshSeed();
  SCOPED_TRACE("seed " + std::to_string(seed));
  std::mt19937_64 rng(seed);
  const Scene scene = scatteredTriangles(rng, 400);
  // Odd counts, some lights past the geometry, radii spread over a decade.
  const std::size_t count = 2049 + 2 * (rng() % 500);
  const auto lights = randomLights(rng, count, kBox, 0.4, 4.0, true);
  for (const char* node : {"0.5r", "1r"}) {
    SCOPED_TRACE(std::string("node ") + node + ", " + std::to_string(count) + " lights");
    HashedConfig cfg;
    cfg.node_size = node;
    cfg.geometry_mask = true;
    Built one, many;
    {
      tbb::global_control gc(tbb::global_control::max_allowed_parallelism, 1);
      one = buildAll(lights, cfg, scene);
    }
    {
      tbb::global_control gc(tbb::global_control::max_allowed_parallelism, 8);
      tbb::task_arena arena(8);
      many = arena.execute([&] { return buildAll(lights, cfg, scene); });
    }
    expectSameOctrees(one.octrees, many.octrees);
    EXPECT_EQ(treeWords(one.hs->tree()), treeWords(many.hs->tree()));
    const LinklessOctree& x = one.hs->linkless();
    const LinklessOctree& y = many.hs->linkless();
    EXPECT_EQ(x.pool().list(), y.pool().list());
    const auto gx = x.packGpuImage(), gy = y.packGpuImage();
    EXPECT_EQ(gx.header, gy.header);
    EXPECT_EQ(gx.offsets, gy.offsets);
    EXPECT_EQ(gx.desc, gy.desc);
    EXPECT_EQ(gx.data, gy.data);
    EXPECT_GT(one.hs->lastBuild().filled_cells, count);  // the case is not trivially empty
  }
}

TEST(HashedBuildThreads, RowLookupListsTheCellsOfThePerCellLookup) {
  const std::uint64_t seed = test::freshSeed();
  SCOPED_TRACE("seed " + std::to_string(seed));
  std::mt19937_64 rng(seed);
  const Scene scene = scatteredTriangles(rng, 300);
  const OctreeBounds b = boundsForBox(glm::dvec3(0), glm::dvec3(kBox), 0.37, 2);
  const GeometryMask mask(scene, b, 0.01);
  const unsigned n = b.cellsPerAxis();
  for (int i = 0; i < 4000; ++i) {
    const unsigned y = unsigned(rng() % n), z = unsigned(rng() % n);
    unsigned lo = unsigned(rng() % n), hi = unsigned(rng() % n);
    if (i % 5 == 0) lo = 0, hi = n - 1;
    if (i % 7 == 0) std::swap(lo, hi);  // empty ranges too
    const auto [first, last] = mask.rowCells(y, z, lo, hi);
    std::size_t at = first;
    for (unsigned x = lo; x <= hi; ++x) {
      const GeometryMask::Box* box = nullptr;
      const GeometryMask::OctantBoxes* oct = mask.octantBoxes({x, y, z}, box);
      if (!oct) continue;
      ASSERT_LT(at, last) << "row " << y << "," << z << " x " << x;
      ASSERT_EQ(mask.cellX(at), x);
      EXPECT_EQ(&mask.cellBox(at), box);
      EXPECT_EQ(&mask.cellOctants(at), oct);
      ++at;
    }
    EXPECT_EQ(at, last) << "row " << y << "," << z << " [" << lo << ", " << hi << "]";
  }
}

// has() below the dense levels (depth 9 and deeper): the deepest level reads
// the row index, the others search the level's keys; both must say what the
// cell lookup says, and a parent holds geometry exactly when a child does.
TEST(HashedBuildThreads, DeepHasMatchesTheCellLookup) {
  const std::uint64_t seed = test::freshSeed();
  SCOPED_TRACE("seed " + std::to_string(seed));
  std::mt19937_64 rng(seed);
  Scene scene;
  std::vector<glm::dvec3> centres;
  for (int t = 0; t < 200; ++t) {
    const glm::dvec3 c(uni(rng, 1, kBox - 1), uni(rng, 1, kBox - 1), uni(rng, 1, kBox - 1));
    centres.push_back(c);
    for (int k = 0; k < 3; ++k) {
      const glm::dvec3 v = c + glm::dvec3(uni(rng, -0.1, 0.1), uni(rng, -0.1, 0.1), uni(rng, -0.1, 0.1));
      scene.vertices.push_back({glm::vec3(v), glm::vec3(0, 1, 0), glm::vec2(0)});
      scene.indices.push_back(std::uint32_t(scene.vertices.size() - 1));
    }
  }
  const OctreeBounds b = boundsForBox(glm::dvec3(0), glm::dvec3(kBox), 0.03, 2);
  ASSERT_GE(b.depth, 10u);
  const GeometryMask mask(scene, b, 0.01);
  std::size_t found = 0;
  for (std::size_t i = 0; i < centres.size() + 2000; ++i) {
    const glm::ivec3 base = i < centres.size() ? glm::ivec3(glm::floor(b.toCells(centres[i])))
                                               : glm::ivec3(int(rng() % b.cellsPerAxis()), int(rng() % b.cellsPerAxis()),
                                                            int(rng() % b.cellsPerAxis()));
    for (int d = 0; d < 27; ++d) {
      const glm::uvec3 c(glm::clamp(base + glm::ivec3(d % 3 - 1, d / 3 % 3 - 1, d / 9 - 1), glm::ivec3(0),
                                    glm::ivec3(int(b.cellsPerAxis()) - 1)));
      const GeometryMask::Box* box = nullptr;
      const bool has = mask.octantBoxes(c, box) != nullptr;
      ASSERT_EQ(mask.has(b.depth, c), has) << c.x << "," << c.y << "," << c.z;
      found += has;
      const glm::uvec3 p = c >> 1u;
      bool any_child = false;
      for (unsigned k = 0; k < 8; ++k) any_child = any_child || mask.octantBoxes(childCoord(p, k), box) != nullptr;
      ASSERT_EQ(mask.has(b.depth - 1, p), any_child) << "parent " << p.x << "," << p.y << "," << p.z;
    }
  }
  EXPECT_GT(found, centres.size()) << "the triangles' cells were found";
}

}  // namespace
}  // namespace ml::hashed
