// Dynamic lights: after random sequences of moves, resizes, additions and
// removals, incremental updates look up exactly what a fresh build of the
// same lights (same bounds) looks up, with the same octree.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "hashed_support.hpp"
#include "host/hashed/DynamicLightUpdater.hpp"
#include "host/hashed/OctantMask.hpp"
#include "host/util/DataPaths.hpp"
#include "support/TestDevice.hpp"

namespace ml::hashed {
namespace {

using namespace test_support;

constexpr double kBox = 50.0;

// One random edit batch, keeping every light inside [0, kBox]^3.
void randomEdits(std::mt19937_64& rng, std::vector<gpu::PointLight>& lights, double fraction, double rmax) {
  auto clampInside = [&](gpu::PointLight& l) {
    const float r = std::min(l.position_radius.w, float(rmax));
    l.position_radius.w = r;
    l.position_radius.x = std::clamp(l.position_radius.x, r, float(kBox) - r);
    l.position_radius.y = std::clamp(l.position_radius.y, r, float(kBox) - r);
    l.position_radius.z = std::clamp(l.position_radius.z, r, float(kBox) - r);
  };
  const std::size_t edits = std::max<std::size_t>(1, std::size_t(double(lights.size()) * fraction));
  for (std::size_t e = 0; e < edits; ++e) {
    const int op = int(rng() % 10);
    if (lights.empty() || op == 9) {  // add
      gpu::PointLight l = makeLight(glm::vec3(uni(rng, 0, kBox), uni(rng, 0, kBox), uni(rng, 0, kBox)),
                                    float(uni(rng, 0.5, rmax)), glm::vec3(1));
      clampInside(l);
      lights.push_back(l);
      continue;
    }
    const std::size_t i = rng() % lights.size();
    if (op == 8) {  // remove: the last light takes the slot
      lights[i] = lights.back();
      lights.pop_back();
    } else if (op == 7) {  // resize
      lights[i].position_radius.w *= float(uni(rng, 0.5, 1.6));
      clampInside(lights[i]);
    } else if (op == 6) {  // colour only: no structural change
      lights[i].color.x = float(uni(rng, 0, 1));
    } else {  // move: mostly small steps, sometimes a jump
      const double step = op == 5 ? kBox * 0.5 : lights[i].position_radius.w * 0.3;
      lights[i].position_radius.x += float(uni(rng, -step, step));
      lights[i].position_radius.y += float(uni(rng, -step, step));
      lights[i].position_radius.z += float(uni(rng, -step, step));
      clampInside(lights[i]);
    }
  }
}

void expectSameAsFreshBuild(const HashedStructure& updated, const Scene* scene, std::mt19937_64& rng,
                            const std::vector<glm::vec3>& points) {
  HashedStructure fresh(updated.config(), scene);
  fresh.build(updated.lights(), updated.bounds());
  expectTablesPerfect(updated.linkless());
  // The same canonical octree, node for node per depth.
  const auto a = updated.tree().countsPerDepth(), b = fresh.tree().countsPerDepth();
  for (std::size_t t = 0; t < a.size(); ++t) {
    EXPECT_EQ(a[t].branches, b[t].branches) << "depth " << t;
    EXPECT_EQ(a[t].filled_leaves, b[t].filled_leaves) << "depth " << t;
  }
  for (unsigned i = 0; i < fresh.linkless().layerCount(); ++i) {
    EXPECT_EQ(updated.linkless().desc(i).size(), fresh.linkless().desc(i).size());
    EXPECT_EQ(updated.linkless().data(i).size(), fresh.linkless().data(i).size());
  }
  // Every leaf's kept element-hash sum matches its set (else equal sets
  // would not find each other in the light set pool).
  updated.tree().forEachNode([](unsigned t, const glm::uvec3&, const SceneOctree::NodeView& v) {
    if (!v.leaf) return;
    std::uint64_t sum = 0;
    for (const auto l : *v.lights) sum += LightSetPool::elementHash(l);
    EXPECT_EQ(v.set_sum, sum) << "leaf at depth " << t;
  });
  for (const auto& p : points) ASSERT_EQ(updated.linkless().lightsAt(p), fresh.linkless().lightsAt(p));
  for (int i = 0; i < 2000; ++i) {
    const glm::vec3 p = randomPointIn(rng, updated.bounds());
    ASSERT_EQ(updated.linkless().lightsAt(p), fresh.linkless().lightsAt(p)) << p.x << "," << p.y << "," << p.z;
  }
}

TEST(HashedDynamic, RandomEditsEqualAFreshBuild) {
  const std::uint64_t seed = test::freshSeed();
  SCOPED_TRACE("seed " + std::to_string(seed));
  std::mt19937_64 rng(seed);
  for (const double fraction : {0.01, 0.1, 0.3}) {
    SCOPED_TRACE("fraction " + std::to_string(fraction));
    auto lights = randomLights(rng, 300, kBox, 1.0, 3.0, false);
    HashedConfig cfg;
    cfg.node_size = "0.5";
    cfg.start_depth = fraction > 0.2 ? 0 : 3;
    cfg.max_incremental_fraction = 1.0;  // always incremental
    HashedStructure hs(cfg);
    hs.build(lights, boundsForBox(glm::dvec3(0), glm::dvec3(kBox), 0.5, cfg.start_depth));
    std::size_t in_place = 0;
    for (int round = 0; round < 8; ++round) {
      randomEdits(rng, lights, fraction, 3.0);
      const UpdateStats& st = hs.update(lights);
      EXPECT_FALSE(st.full_rebuild) << st.reason;
      in_place += st.sync.in_place;
      expectSameAsFreshBuild(hs, nullptr, rng, {});
      if (HasFailure()) return;
    }
    EXPECT_GT(in_place, 0u);
  }
}

// Batches large enough for the parallel paths: octrees built while the
// edits consume them, the per-key derivation and the per-table writes in
// parallel, and compactions of a light index list past 16K entries.
TEST(HashedDynamic, LargeRandomBatchesEqualAFreshBuild) {
  const std::uint64_t seed = test::freshSeed();
  SCOPED_TRACE("seed " + std::to_string(seed));
  std::mt19937_64 rng(seed);
  auto lights = randomLights(rng, 2000, kBox, 1.0, 3.0, false);
  HashedConfig cfg;
  cfg.node_size = "0.5";
  cfg.max_incremental_fraction = 1.0;
  HashedStructure hs(cfg);
  hs.build(lights, boundsForBox(glm::dvec3(0), glm::dvec3(kBox), 0.5, cfg.start_depth));
  std::size_t max_keys = 0, max_moved = 0, compactions = 0;
  // Garbage grows with every update until it outweighs the live entries, and
  // the compaction runs at the start of the update after that: keep going
  // (up to 16 rounds) until one has run, whatever the random edits were.
  // Deepest leaves rewrite their ranges in place (octant masks), so garbage
  // comes slower than with shared ranges only: edits of 20% and 40% of the
  // lights bring the first compaction at the 11th update (10% / 30% took up
  // to 17 updates, past the limit for some seeds).
  for (int round = 0; round < 16 && (round < 8 || compactions == 0); ++round) {
    randomEdits(rng, lights, round % 2 ? 0.4 : 0.2, 3.0);
    const UpdateStats& st = hs.update(lights);
    EXPECT_FALSE(st.full_rebuild) << st.reason;
    max_keys = std::max(max_keys, st.sync.keys);
    max_moved = std::max(max_moved, st.moved);
    compactions += st.sync.compacted;
    // A fresh build per round would be most of the test's time (under the
    // sanitizers, minutes): every third round, the compacting one, and the last.
    if (round % 3 == 0 || st.sync.compacted) expectSameAsFreshBuild(hs, nullptr, rng, {});
    if (HasFailure()) return;
  }
  expectSameAsFreshBuild(hs, nullptr, rng, {});
  EXPECT_GE(max_moved, 64u);
  EXPECT_GE(max_keys, 2048u);
  EXPECT_GT(compactions, 0u);
  EXPECT_GT(hs.linkless().pool().list().size(), 16384u);
}

// With the geometry mask (geometry-tight light sets) the updates edit by
// light octrees.
TEST(HashedDynamic, RandomEditsWithGeometryMaskEqualAFreshBuild) {
  const std::uint64_t seed = test::freshSeed();
  SCOPED_TRACE("seed " + std::to_string(seed));
  std::mt19937_64 rng(seed);
  const Scene scene = loadGltfScene(dataPath("default/scene.glb"));
  std::vector<glm::vec3> surface;
  for (int i = 0; i < 3000; ++i) surface.push_back(glm::vec3(randomSurfacePoint(rng, scene)));
  // Lights inside the default scene's main hall and rooms.
  std::vector<gpu::PointLight> lights = loadLightsJson(dataPath("default/lights.json"));
  lights.resize(300);
  HashedConfig cfg;
  cfg.node_size = "0.5r";
  cfg.geometry_mask = true;
  cfg.bounds_padding = 0.2;
  cfg.max_incremental_fraction = 1.0;
  HashedStructure hs(cfg, &scene);
  hs.build(lights);
  int incremental = 0;
  for (int round = 0; round < 8; ++round) {
    for (int e = 0; e < 30; ++e) {
      auto& l = lights[rng() % lights.size()];
      l.position_radius.x += float(uni(rng, -0.8, 0.8));
      l.position_radius.z += float(uni(rng, -0.8, 0.8));
      l.position_radius.w *= float(uni(rng, 0.8, 1.2));
    }
    const UpdateStats& st = hs.update(lights);
    if (st.full_rebuild) continue;  // a light left the padded bounds: nothing incremental to check
    ++incremental;
    expectSameAsFreshBuild(hs, &scene, rng, surface);
    if (HasFailure()) return;
  }
  EXPECT_GE(incremental, 3);
}

TEST(HashedDynamic, LeavingTheBoundsOrMovingMostLightsRebuilds) {
  std::mt19937_64 rng(3);
  auto lights = randomLights(rng, 50, kBox, 1.0, 2.0, false);
  HashedConfig cfg;
  cfg.node_size = "1.0";
  HashedStructure hs(cfg);
  EXPECT_TRUE(hs.update(lights).full_rebuild);  // the first update builds
  lights[3].position_radius.x = 1000.0f;
  const UpdateStats& st = hs.update(lights);
  EXPECT_TRUE(st.full_rebuild);
  EXPECT_EQ(hs.linkless().lightsAt({1000.0f, lights[3].position_radius.y, lights[3].position_radius.z}),
            std::vector<std::uint32_t>{3});
  for (auto& l : lights) l.position_radius.y += 0.1f;
  EXPECT_TRUE(hs.update(lights).full_rebuild);
  lights[0].color.y = 0.25f;
  const UpdateStats& colour = hs.update(lights);
  EXPECT_FALSE(colour.full_rebuild);
  EXPECT_EQ(colour.sync.keys, 0u);
}

}  // namespace
}  // namespace ml::hashed

