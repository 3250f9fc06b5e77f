// The parallel tree edit (SceneOctree::replaceAll: one task per subtree at
// depth 2) against one replace() at a time, with lights that span several
// subtrees, sit on the subtrees' shared faces or touch the bounds; and whole
// updates on 1 and 4 threads: identical light index lists and hash tables,
// word for word.
#include <gtest/gtest.h>
#include <tbb/task_arena.h>

#include <random>
#include <tuple>

#include "hashed_support.hpp"
#include "host/hashed/LightOctreeBuilder.hpp"
#include "host/hashed/SceneOctree.hpp"
#include "support/TestDevice.hpp"

namespace ml::hashed {
namespace {

using namespace test_support;

constexpr double kBox = 50.0;

float& axis(gpu::PointLight& l, int a) {
  return a == 0 ? l.position_radius.x : a == 1 ? l.position_radius.y : l.position_radius.z;
}

using NodeDump = std::vector<std::tuple<unsigned, std::uint64_t, bool, std::vector<std::uint32_t>>>;
NodeDump dump(const SceneOctree& tree) {
  NodeDump out;
  tree.forEachNode([&](unsigned t, const glm::uvec3& c, const SceneOctree::NodeView& v) {
    out.emplace_back(t, nodeKey(t, c), v.leaf, v.leaf ? *v.lights : std::vector<std::uint32_t>{});
  });
  return out;
}

// `one` has had the batch replaced one light at a time; par1 and parN get it
// by replaceAll() on 1 and 4 threads. All three normalized must agree; the
// sequential result is returned.
NodeDump expectReplaceAllAgrees(SceneOctree& one, SceneOctree& par1, SceneOctree& parN,
                                const std::vector<SceneOctree::CellsReplacement>& batch, int round) {
  tbb::task_arena(1).execute([&] { par1.replaceAll(batch); });
  tbb::task_arena(4).execute([&] { parN.replaceAll(batch); });
  for (auto* t : {&one, &par1, &parN}) t->normalize();
  NodeDump want = dump(one);
  EXPECT_TRUE(dump(par1) == want) << "round " << round << ", 1 thread";
  EXPECT_TRUE(dump(parN) == want) << "round " << round << ", 4 threads";
  return want;
}

// Random lights plus lights centred on the faces, edges and corners shared by
// the depth-1 and depth-2 subtrees, some large enough to span many of them.
// `inside`: every sphere inside the box (updates then never leave the bounds).
std::vector<gpu::PointLight> partitionStressLights(std::mt19937_64& rng, const OctreeBounds& b, bool inside) {
  auto lights = randomLights(rng, 300, kBox, 1.0, 3.0, !inside);
  const double side = b.cell_size * double(1u << b.depth);
  for (const double f : {0.25, 0.5, 0.75})
    for (int i = 0; i < 12; ++i) {
      glm::dvec3 p(uni(rng, 0, kBox), uni(rng, 0, kBox), uni(rng, 0, kBox));
      const int axes = 1 + int(rng() % 3);  // a face, an edge or a corner
      for (int a = 0; a < axes; ++a) p[(i + a) % 3] = b.origin[(i + a) % 3] + f * side;
      const float r = i % 4 == 0 ? float(uni(rng, 6, inside ? 8 : 20)) : float(uni(rng, 0.5, 3));
      lights.push_back(makeLight(glm::vec3(p), r, glm::vec3(1)));
    }
  for (auto& l : lights)  // centres inside the box the bounds were made for
    for (int a = 0; a < 3; ++a) {
      const float margin = inside ? l.position_radius.w : 0.0f;
      axis(l, a) = std::clamp(axis(l, a), margin, float(kBox) - margin);
    }
  return lights;
}

// A fresh seed, bounds with room for depth-2 subtrees below the start
// depth, and partitionStressLights() in them.
struct StressCase {
  std::uint64_t seed;
  std::mt19937_64 rng;
  OctreeBounds b;
  std::vector<gpu::PointLight> lights;
  explicit StressCase(bool inside)
      : seed(test::freshSeed()), rng(seed), b(boundsForBox(glm::dvec3(0), glm::dvec3(kBox), 0.5, 3)),
        lights(partitionStressLights(rng, b, inside)) {}
};

// Versions given as LightCells (the update path without geometry-tight
// sets), with moved, added and removed lights (no version); partitionStressLights()' large
// lights have worst-case splits above the free blocks, so they wait for the
// sequential pass after the parallel one.
TEST(HashedParallelEdit, CellsReplaceAllEqualsOneReplaceAtATime) {
  StressCase sc(true);
  SCOPED_TRACE("seed " + std::to_string(sc.seed));
  ASSERT_GE(sc.b.start_depth, 2u);
  auto& [seed, rng, b, lights] = sc;
  const std::size_t removed_from = lights.size() - 5;  // the last 5 are removed, 5 new ones added
  LightGridScratch scratch;
  for (int round = 0; round < 2; ++round) {
    SceneOctree one(b, nullptr), par1(b, nullptr), parN(b, nullptr);
    for (auto* t : {&one, &par1, &parN}) {
      for (std::uint32_t i = 0; i < lights.size(); ++i) t->insert(buildLightOctree(lights[i], i, b, scratch));
      t->normalize();
    }
    std::vector<LightCells> versions;
    std::vector<std::uint32_t> which;
    auto next = lights;
    for (std::uint32_t i = 0; i < lights.size(); ++i) {
      if (i < removed_from && rng() % 3) continue;
      auto& l = next[i];
      const double step = rng() % 4 == 0 ? kBox * 0.5 : l.position_radius.w * 0.5;
      for (int a = 0; a < 3; ++a)
        axis(l, a) = std::clamp(axis(l, a) + float(uni(rng, -step, step)), 0.0f, float(kBox));
      if (rng() % 5 == 0) l.position_radius.w *= float(uni(rng, 0.5, 2.0));
      which.push_back(i);
    }
    versions.reserve(2 * which.size() + 10);
    std::vector<SceneOctree::CellsReplacement> batch;
    for (const auto i : which) {
      versions.emplace_back(lights[i], b);
      const LightCells* old_version = &versions.back();
      const bool removed = i >= removed_from;
      if (!removed) versions.emplace_back(next[i], b);
      batch.push_back({old_version, removed ? nullptr : &versions.back(), i});
    }
    next.resize(removed_from);
    for (std::uint32_t k = 0; k < 5; ++k) {  // added at the removed ones' indices
      next.push_back(makeLight(glm::vec3(uni(rng, 0, kBox), uni(rng, 0, kBox), uni(rng, 0, kBox)),
                               float(uni(rng, 0.5, 3)), glm::vec3(1)));
      versions.emplace_back(next.back(), b);
      batch.push_back({nullptr, &versions.back(), std::uint32_t(removed_from + k)});
    }
    ASSERT_GE(batch.size(), 32u);  // replaceAll's parallel path
    for (const auto& r : batch) one.replace(r.old_version ? *r.old_version : LightCells(),
                                            r.new_version ? *r.new_version : LightCells(), r.light);
    const NodeDump want = expectReplaceAllAgrees(one, par1, parN, batch, round);
    lights = next;
    SceneOctree fresh(b, nullptr);
    for (std::uint32_t i = 0; i < lights.size(); ++i) fresh.insert(buildLightOctree(lights[i], i, b, scratch));
    fresh.normalize();
    EXPECT_TRUE(dump(fresh) == want) << "round " << round;
    if (HasFailure()) return;
  }
}

TEST(HashedParallelEdit, UpdatesDoNotDependOnTheThreadCount) {
  const std::uint64_t seed = test::freshSeed();
  SCOPED_TRACE("seed " + std::to_string(seed));
  std::mt19937_64 rng(seed);
  HashedConfig cfg;
  cfg.node_size = "0.5";
  cfg.max_incremental_fraction = 1.0;
  const OctreeBounds b = boundsForBox(glm::dvec3(0), glm::dvec3(kBox), 0.5, cfg.start_depth);
  auto lights = partitionStressLights(rng, b, true);
  HashedStructure one(cfg), many(cfg);
  tbb::task_arena a1(1), a4(4);
  a1.execute([&] { one.build(lights, b); });
  a4.execute([&] { many.build(lights, b); });
  for (int round = 0; round < 6; ++round) {
    for (auto& l : lights) {
      if (rng() % 4) continue;
      const float r = l.position_radius.w, step = r * 0.4f;
      for (int a = 0; a < 3; ++a)
        axis(l, a) = std::clamp(axis(l, a) + float(uni(rng, -step, step)), r, float(kBox) - r);
    }
    const UpdateStats s1 = a1.execute([&] { return one.update(lights); });
    const UpdateStats s4 = a4.execute([&] { return many.update(lights); });
    ASSERT_FALSE(s1.full_rebuild) << s1.reason;
    ASSERT_FALSE(s4.full_rebuild) << s4.reason;
    EXPECT_GE(s1.moved, 32u);
    const LinklessOctree& x = one.linkless();
    for (const LinklessOctree* y : {&many.linkless()}) {
      EXPECT_EQ(x.pool().list(), y->pool().list()) << "round " << round;
      ASSERT_EQ(x.layerCount(), y->layerCount());
      for (unsigned i = 0; i < x.layerCount(); ++i) {
        EXPECT_EQ(x.desc(i).tableWords(), y->desc(i).tableWords()) << "layer " << i;
        EXPECT_EQ(x.desc(i).offsetWords(), y->desc(i).offsetWords()) << "layer " << i;
        EXPECT_EQ(x.data(i).tableWords(), y->data(i).tableWords()) << "layer " << i;
        EXPECT_EQ(x.data(i).offsetWords(), y->data(i).offsetWords()) << "layer " << i;
      }
    }
    HashedStructure fresh(cfg);
    fresh.build(lights, b);
    for (int i = 0; i < 1000; ++i) {
      const glm::vec3 p = randomPointIn(rng, b);
      ASSERT_EQ(x.lightsAt(p), fresh.linkless().lightsAt(p));
    }
    if (HasFailure()) return;
  }
}

}  // namespace
}  // namespace ml::hashed
