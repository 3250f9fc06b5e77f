// The real thesis suite (spaceship-indoor) when it is present: the loader's
// object/mesh/camera/light counts, the missing Junction-4 mesh, the reference
// layout, and one frame of our naive count against the thesis's (x10). The
// suite is an input, not a dependency: without it these tests skip, visibly.
// Location: $MANYLIGHTS_THESIS_SUITE, else ../shared/data/thesis-suite next
// to the source tree.
#include "ml_build_paths.h"  // MANYLIGHTS_SOURCE_DIR (generated)
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <cstdlib>
#include <filesystem>
#include <fstream>

#include "host/suite/NtiledSuite.hpp"
#include "host/suite/ThesisReference.hpp"
#include "host/util/Error.hpp"
#include "support/RunCommand.hpp"

namespace ml {
namespace {

namespace fs = std::filesystem;

std::string thesisSuite() {
  if (const char* env = std::getenv("MANYLIGHTS_THESIS_SUITE"); env && *env) return env;
  return (fs::path(MANYLIGHTS_SOURCE_DIR) / ".." / "shared" / "data" / "thesis-suite").lexically_normal().string();
}

std::string sceneDir() { return thesisSuite() + "/scenes/spaceship-indoor"; }

#define REQUIRE_THESIS_SUITE()                                                                                   \
  if (!isNtiledSuiteDir(sceneDir()))                                                                             \
  GTEST_SKIP() << "thesis suite not found at " << thesisSuite()                                                  \
               << " (set MANYLIGHTS_THESIS_SUITE to the thesis-suite folder); the generated suite tests cover the " \
                  "same code paths"

TEST(SuiteThesis, LoadsSpaceshipIndoor) {
  REQUIRE_THESIS_SUITE();
  SuiteLoadOptions o;
  o.allow_missing_meshes = true;
  const SuiteScene s = loadNtiledSuite(sceneDir(), o);
  EXPECT_EQ(s.name, "spaceship-indoor");
  EXPECT_EQ(s.objects.size(), 191u);
  EXPECT_EQ(s.placed_objects, 190u);
  ASSERT_EQ(s.missing_meshes.size(), 1u);
  EXPECT_EQ(s.missing_meshes[0], "Junction-4");
  EXPECT_GT(s.scene.triangleCount(), 4'000'000u);
  EXPECT_EQ(s.cameras.frames.size(), 519u);
  EXPECT_EQ(s.cameras.frames[3].fovy_degrees, 45.0f);
  EXPECT_EQ(s.light_files.size(), 27u);
  const auto thesis = thesisLightFiles(s.light_files);
  ASSERT_EQ(thesis.size(), 10u);
  EXPECT_EQ(fs::path(thesis.front()).filename(), "70#1x_1y_1z.json");
  EXPECT_EQ(fs::path(thesis[1]).filename(), "140#2x_1y_1z.json");
  EXPECT_EQ(fs::path(thesis.back()).filename(), "1890#3x_3y_3z.json");

  try {
    loadNtiledSuite(sceneDir());
    FAIL() << "Junction-4.obj is missing from the published copy";
  } catch (const UserError& e) {
    EXPECT_NE(std::string(e.what()).find("Junction-4.obj"), std::string::npos) << e.what();
  }
}

TEST(SuiteThesis, ReferenceLayout) {
  REQUIRE_THESIS_SUITE();
  const ThesisReference ref = loadThesisReference(thesisSuite(), "spaceship-indoor");
  std::vector<std::string> ids;
  for (const auto& s : ref.series) ids.push_back(s.id);
  EXPECT_EQ(ids, (std::vector<std::string>{"ns", "ts/8", "ts/16", "ts/32", "ts/64", "cs/8", "cs/16", "cs/32"}));
  for (const auto& s : ref.series) {
    EXPECT_EQ(s.counts.size(), 516u) << s.id;
    EXPECT_EQ(s.counts.begin()->first, 3u);
    EXPECT_EQ(s.width, 320u);
    EXPECT_EQ(s.light_file, "70#1x_1y_1z.json");
  }
  // The naive series never exceeds a tenth of NUM_LIGHTS x pixels: it is stored /10.
  double max_ns = 0;
  for (const auto& [f, c] : ref.series[0].counts) max_ns = std::max(max_ns, c);
  EXPECT_EQ(max_ns, 70.0 * 320 * 320 / 10);
}

TEST(SuiteThesis, NaiveCountOfAFullyCoveredFrameMatches) {
  REQUIRE_THESIS_SUITE();
  const std::string json = test::tempDir() + "/thesis-compare.json";
  // Frame 131 looks down a corridor away from the missing hub mesh.
  auto r = test::runManylights("compare-reference --reference " + thesisSuite() + " --suite " + sceneDir() +
                               " --allow-missing-meshes --techniques deferred --frames 131 --progress none --json " +
                               json);
  ASSERT_EQ(r.exit_code, 0) << r.err << r.out;
  std::ifstream in(json);
  const auto j = nlohmann::json::parse(in);
  const auto& ns = j["series"][0];
  ASSERT_EQ(ns["series"], "ns");
  ASSERT_EQ(ns["frames"].size(), 1u);
  EXPECT_NEAR(ns["ratio"]["mean"].get<double>(), 1.0, 0.01) << "ours " << ns["ours"] << " thesis " << ns["thesis"];
}

}  // namespace
}  // namespace ml
