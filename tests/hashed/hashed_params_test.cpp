// Bad hashed-shading parameters are user errors naming the flag, found
// before anything large is allocated.
#include <gtest/gtest.h>

#include <chrono>
#include <random>

#include "hashed_support.hpp"
#include "host/hashed/OctantMask.hpp"
#include "host/util/Error.hpp"
#include "support/RunCommand.hpp"
#include "support/TestDevice.hpp"

namespace ml::hashed {
namespace {

template <class F>
std::string userErrorOf(F&& f) {
  try {
    f();
  } catch (const UserError& e) {
    return e.what();
  }
  return "(no UserError)";
}

TEST(HashedParams, NodeSizeMustBeAPositiveNumber) {
  for (const char* bad : {"0", "-1", "0r", "-0.5r", "abc", "r", "", "nan", "1e400", "2x"}) {
    const std::string msg = userErrorOf([&] { parseNodeSize(bad); });
    EXPECT_NE(msg.find("--node-size"), std::string::npos) << bad << ": " << msg;
  }
  EXPECT_DOUBLE_EQ(parseNodeSize("0.5r").value, 0.5);
  EXPECT_TRUE(parseNodeSize("0.5r").relative);
  EXPECT_FALSE(parseNodeSize("2").relative);
  HashedConfig cfg;
  cfg.node_size = "0";
  EXPECT_NE(userErrorOf([&] { HashedStructure hs(cfg); }).find("--node-size"), std::string::npos);
}

// Light indices share a list word with the octant mask: 24 bits.
TEST(HashedParams, MoreLightsThanTheEntryFormatHoldsAreRefused) {
  EXPECT_EQ(userErrorOf([] { HashedStructure::checkLightCount(kMaxHashedLights); }), "(no UserError)");
  const std::string msg = userErrorOf([] { HashedStructure::checkLightCount(std::size_t(kMaxHashedLights) + 1); });
  EXPECT_NE(msg.find("--lights"), std::string::npos) << msg;
  EXPECT_NE(msg.find(std::to_string(kMaxHashedLights)), std::string::npos) << msg;
}

// Relative node sizes scale the median radius (the typical light), not the
// largest or the mean; absolute sizes are taken as given.
TEST(HashedParams, RelativeNodeSizeUsesTheMedianRadius) {
  std::vector<gpu::PointLight> lights;
  for (const float r : {9.0f, 2.0f, 2.0f, 30.0f, 2.0f})
    lights.push_back(makeLight({float(lights.size()) * 10.0f, 0, 0}, r, glm::vec3(1)));
  for (const auto& [spec, want] : {std::pair<std::string, double>{"0.5r", 1.0}, {"2r", 4.0}, {"3", 3.0}}) {
    HashedConfig cfg;
    cfg.node_size = spec;
    EXPECT_DOUBLE_EQ(computeBounds(lights, cfg).cell_size, want) << spec;
  }
}

TEST(HashedParams, HugeFootprintsAreRefusedBeforeAllocating) {
  std::mt19937_64 rng(1);
  const auto lights = test_support::randomLights(rng, 20000, 100.0, 1.0, 1.0, false);
  HashedConfig cfg;
  cfg.node_size = "0.02r";  // ~100^3 cells per light: ~20 billion (light, cell) pairs
  const auto t0 = std::chrono::steady_clock::now();
  const std::string msg = userErrorOf([&] {
    HashedStructure hs(cfg);
    hs.build(lights);
  });
  const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  EXPECT_NE(msg.find("--node-size"), std::string::npos) << msg;
  EXPECT_NE(msg.find("GiB"), std::string::npos) << msg;
  EXPECT_LT(s, 1.0) << "the check must not build anything";

  // More cells per axis than the key packing allows.
  const std::vector<gpu::PointLight> two = {makeLight({0, 0, 0}, 1.0f, glm::vec3(1)),
                                            makeLight({1e5f, 0, 0}, 1.0f, glm::vec3(1))};
  cfg.node_size = "0.5";
  const std::string deep = userErrorOf([&] { computeBounds(two, cfg); });
  EXPECT_NE(deep.find("--node-size"), std::string::npos) << deep;

  // A configurable limit.
  cfg.node_size = "0.5r";
  cfg.memory_limit = 1 << 16;
  EXPECT_NE(userErrorOf([&] { computeBounds(lights, cfg); }).find("limit"), std::string::npos);
}

TEST(HashedParams, GeometryMaskNeedsASceneAndFitsTheLimit) {
  HashedConfig cfg;
  cfg.geometry_mask = true;
  EXPECT_NE(userErrorOf([&] { HashedStructure hs(cfg, nullptr); }).find("--geometry-mask"), std::string::npos);
  // A big floor at a tiny node size: refused while voxelising, when the
  // mask's buffers pass the limit (64 MiB here, so it stops soon).
  Scene floor;
  for (const glm::vec3 p : {glm::vec3(-50, 0, -50), glm::vec3(50, 0, -50), glm::vec3(50, 0, 50), glm::vec3(-50, 0, 50)})
    floor.vertices.push_back({p, glm::vec3(0, 1, 0), glm::vec2(0)});
  floor.indices = {0, 1, 2, 0, 2, 3};
  cfg.node_size = "0.01";
  cfg.memory_limit = std::size_t(64) << 20;
  HashedStructure hs(cfg, &floor);
  const gpu::PointLight small = makeLight({0, 1, 0}, 0.02f, glm::vec3(1));  // the light alone fits easily
  const std::string msg = userErrorOf([&] { hs.build({small}, boundsForBox(glm::dvec3(-50), glm::dvec3(50), 0.01, 3)); });
  EXPECT_NE(msg.find("geometry mask"), std::string::npos) << msg;
  EXPECT_NE(msg.find("--node-size"), std::string::npos) << msg;
}

// With the mask, the first check counts the light octrees only; the lit
// cells with geometry, counted as the octrees are built, are checked before
// each chunk of them is merged: a limit between the two estimates refuses
// the build, and one at the second lets it through.
TEST(HashedParams, GeometryMaskBuildsCheckTheirLitCells) {
  const std::uint64_t seed = test::freshSeed();
  SCOPED_TRACE("seed " + std::to_string(seed));
  std::mt19937_64 rng(seed);
  Scene floor;
  for (const glm::vec3 p : {glm::vec3(0, 1, 0), glm::vec3(20, 1, 0), glm::vec3(20, 1, 20), glm::vec3(0, 1, 20)})
    floor.vertices.push_back({p, glm::vec3(0, 1, 0), glm::vec2(0)});
  floor.indices = {0, 1, 2, 0, 2, 3};
  std::vector<gpu::PointLight> lights;
  for (int i = 0; i < 2000 + int(rng() % 100); ++i)  // on the floor: many lit cells per light
    lights.push_back(makeLight({float(test_support::uni(rng, 2, 18)), 1.0f, float(test_support::uni(rng, 2, 18))},
                               float(test_support::uni(rng, 2.8, 3.2)), glm::vec3(1)));
  HashedConfig cfg;
  cfg.geometry_mask = true;
  cfg.node_size = "0.25r";
  HashedStructure probe(cfg, &floor);
  probe.build(lights);
  const std::size_t first = estimateBuildBytes(lights, probe.bounds(), true);
  const std::size_t lit = estimateLitBytes(lights.size(), probe.lastBuild().filled_cells);
  const std::size_t mask_need = probe.lastBuild().mask_bytes;  // checked on its own, as it grows
  ASSERT_LT(std::max(first, mask_need), lit);
  EXPECT_LT(first, estimateBuildBytes(lights, probe.bounds(), false));  // the mask's point
  cfg.memory_limit = (std::max(first, mask_need) + lit) / 2;
  HashedStructure refused(cfg, &floor);
  const std::string msg = userErrorOf([&] { refused.build(lights); });
  EXPECT_NE(msg.find("--node-size 0.25r"), std::string::npos) << msg;
  EXPECT_FALSE(refused.built());
  cfg.memory_limit = lit;
  HashedStructure fits(cfg, &floor);
  fits.build(lights);
  EXPECT_EQ(fits.linkless().pool().list(), probe.linkless().pool().list());
}

TEST(HashedParams, RenderCommandReportsTheFlag) {
  const auto r = test::runManylights("render --technique hashed-deferred --node-size 0 --size 32x18");
  EXPECT_EQ(r.exit_code, 2) << r.out << r.err;
  EXPECT_NE((r.out + r.err).find("--node-size"), std::string::npos) << r.out << r.err;
}

// --animate moves lights between timed frames: hashed updates incrementally.
TEST(HashedParams, AnimateUpdatesIncrementally) {
  const auto r = test::runManylights("render --technique hashed-deferred --size 64x36 --frames 3 --animate 0.05");
  EXPECT_EQ(r.exit_code, 0) << r.out << r.err;
  EXPECT_NE(r.out.find("hashed-update"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("updates"), std::string::npos) << r.out;
  const auto bad = test::runManylights("render --technique hashed-deferred --size 64x36 --animate 2");
  EXPECT_EQ(bad.exit_code, 2);
  EXPECT_NE((bad.out + bad.err).find("--animate"), std::string::npos) << bad.out << bad.err;
}

}  // namespace
}  // namespace ml::hashed
