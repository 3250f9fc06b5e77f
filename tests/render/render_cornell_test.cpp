// The Cornell box (data/cornell, scripts/make_cornell_box.py) renders with every
// built-in technique through the render command (a separate process: a render
// in this process would end the tests' shared GL context): no light a pixel's surface
// lies in is missed, the box fills most of the frame, and its lights reach it.
#include <gtest/gtest.h>

#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "host/techniques/Registry.hpp"
#include "ml_test_paths.h"  // MANYLIGHTS_TEST_DATA_DIR
#include "support/RunCommand.hpp"
#include "support/TempDir.hpp"

namespace ml {
namespace {

std::vector<std::string> splitNames(const std::string& names) {
  std::vector<std::string> out;
  std::stringstream ss(names);
  for (std::string n; std::getline(ss, n, '|');) out.push_back(n);
  return out;
}

TEST(RenderCornell, EveryTechniqueRendersTheBox) {
  const std::string dir = std::string(MANYLIGHTS_TEST_DATA_DIR) + "/cornell/";
  test::TempDir tmp;
  std::vector<std::string> names;
  for (const std::string& t : splitNames(techniqueNames()))
    if (findTechnique(t).built_in) names.push_back(t);
  ASSERT_GE(names.size(), 8u);
  for (const std::string& t : names) {
    SCOPED_TRACE(t);
    const std::string stats = tmp.file(t + ".json");
    const auto r = test::runManylights("render --scene " + dir + "cornell.gltf --lights " + dir + "lights.json --camera " +
                                       dir + "camera.json --technique " + t +
                                       " --size 64x36 --frames 1 --warmup 0 --stats-json " + stats);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const nlohmann::json j = nlohmann::json::parse(std::ifstream(stats));
    EXPECT_EQ(j.at("lights").get<int>(), 4);
    EXPECT_EQ(j.at("missed_lights").get<std::uint64_t>(), 0u);
    EXPECT_GT(j.at("covered_pixels").get<std::uint64_t>(), 64u * 36u / 2);
    EXPECT_GT(j.at("lower_bound").get<std::uint64_t>(), j.at("covered_pixels").get<std::uint64_t>());
  }
}

}  // namespace
}  // namespace ml
