// Whole updates on 1 and 4 threads, with lights that span several depth-2
// subtrees, sit on their shared faces or touch the bounds: identical light
// index lists and hash tables, word for word.
#include <gtest/gtest.h>
#include <tbb/task_arena.h>

#include <random>

#include "hashed_support.hpp"
#include "support/TestDevice.hpp"

namespace ml::hashed {
namespace {

using namespace test_support;

constexpr double kBox = 50.0;

float& axis(gpu::PointLight& l, int a) {
  return a == 0 ? l.position_radius.x : a == 1 ? l.position_radius.y : l.position_radius.z;
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

TEST(HashedThreads, UpdatesDoNotDependOnTheThreadCount) {
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
