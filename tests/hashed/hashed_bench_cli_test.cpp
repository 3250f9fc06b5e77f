// The bench command with moving lights (--animate) on hashed shading.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <fstream>
#include <string>

#include "support/RunCommand.hpp"

namespace ml {
namespace {

// `bench --animate`: every counted and timed render of a frame follows moved
// lights, so hashed runs report the incremental update as a pass and still
// respect the exact lower bound (which is computed from the moved lights).
TEST(HashedParams, BenchAnimateReportsUpdates) {
  const std::string json = test::tempDir() + "/bench-animate.json";
  const auto r = test::runManylights("bench --techniques hashed-deferred --lights 64 --size 48x32 --frames 0:1 "
                                     "--repeat 2 --warmup 1 --animate 0.1 --progress none --json " + json);
  ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
  std::ifstream in(json);
  const auto j = nlohmann::json::parse(in);
  EXPECT_DOUBLE_EQ(j["meta"]["animate"].get<double>(), 0.1);
  ASSERT_EQ(j["records"].size(), 2u);
  for (const auto& rec : j["records"]) {
    ASSERT_TRUE(rec["passes"].contains("hashed-update")) << rec["passes"].dump();
    EXPECT_FALSE(rec["passes"].contains("hashed-build")) << "the build belongs to the warm-up";
    EXPECT_GE(rec["light_evaluations"].get<double>(), rec["lower_bound"].get<double>());
  }
  const auto bad = test::runManylights("bench --techniques hashed-deferred --lights 64 --animate 1.5");
  EXPECT_EQ(bad.exit_code, 2);
  EXPECT_NE((bad.out + bad.err).find("--animate"), std::string::npos) << bad.out << bad.err;
}

// geometry_mask=on reaches the hashed assigner with the scene's triangles
// (without them it refuses to build), and the masked lists stay conservative.
TEST(HashedParams, BenchGeometryMask) {
  const std::string json = test::tempDir() + "/bench-mask.json";
  const auto r = test::runManylights("bench --techniques hashed-deferred --lights 64 --size 48x32 --frames 0 "
                                     "--param geometry_mask=on --no-timing --progress none --json " + json);
  ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
  std::ifstream in(json);
  const auto j = nlohmann::json::parse(in);
  ASSERT_EQ(j["records"].size(), 1u);
  EXPECT_GE(j["records"][0]["light_evaluations"].get<double>(), j["records"][0]["lower_bound"].get<double>());
}

}  // namespace
}  // namespace ml
