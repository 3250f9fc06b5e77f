// `manylights compare-reference` on a tiny synthetic reference in the thesis's
// layout: naive counts are compared after x10 (the thesis's ns data is
// NUM_LIGHTS x covered / 10), techniques not registered in this build are
// skipped with a visible note, and the tables/JSON/CSV/Markdown come out.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "host/techniques/Registry.hpp"
#include "host/suite/ThesisReference.hpp"
#include "host/util/Error.hpp"
#include "suite/suite_support.hpp"
#include "support/RunCommand.hpp"

namespace ml {
namespace {

namespace fs = std::filesystem;
using test::runManylights;

bool registered(const std::string& name) {
  for (const auto& t : techniques())
    if (t.name == name) return true;
  return false;
}

// <root>/reference/light_calculations/frames/{ns, ts/16, cs/16, cs/64 (config only)}/deferred/<scene>/
std::string writeReference(const std::string& root, const std::string& scene) {
  const fs::path frames = fs::path(root) / "reference" / "light_calculations" / "frames";
  const std::string config =
      "{\"viewport\": {\"width\": 32, \"height\": 32}, \"tile_size\": {\"x\": 16, \"y\": 16}, "
      "\"lights\": [{\"path\": \"C:\\\\Users\\\\someone\\\\suite\\\\lights\\\\10#1x_1y_1z.json\"}], "
      "\"camera\": {\"fovy\": 45.0, \"aspect\": 1.0, \"clip\": {\"near\": 0.01, \"far\": 4000.0}}}";
  auto lc = [](double a, double b, double c) {
    return "{\"frames\":[{\"frame\":0,\"n_calc\":" + std::to_string(a) + "},{\"frame\":1,\"n_calc\":" +
           std::to_string(b) + "},{\"frame\":2,\"n_calc\":" + std::to_string(c) + "}]}";
  };
  // 10 lights x 1024 covered pixels / 10, as the thesis stores naive counts.
  test::writeText(frames / "ns" / "deferred" / scene / "lc_data.json", lc(1024, 1024, 1024));
  test::writeText(frames / "ns" / "deferred" / scene / "config.json", config);
  test::writeText(frames / "ts" / "deferred" / scene / "16" / "lc_data.json", lc(5000, 5000, 2500));
  test::writeText(frames / "ts" / "deferred" / scene / "16" / "config.json", config);
  test::writeText(frames / "cs" / "deferred" / scene / "16" / "lc_data.json", lc(3000, 3000, 3000));
  test::writeText(frames / "cs" / "deferred" / scene / "16" / "config.json", config);
  test::writeText(frames / "cs" / "deferred" / scene / "64" / "config.json", config);
  return root;
}

TEST(BenchCompareReference, ReadsTheThesisLayout) {
  const std::string root = writeReference(test::tempDir() + "/ref-read", "small-scene");
  for (const std::string& dir : {root, root + "/reference", root + "/reference/light_calculations",
                                root + "/reference/light_calculations/frames"}) {
    const ThesisReference ref = loadThesisReference(dir, "");
    EXPECT_EQ(ref.scene, "small-scene");
    ASSERT_EQ(ref.series.size(), 3u) << dir;
    EXPECT_EQ(ref.series[0].id, "ns");
    EXPECT_EQ(ref.series[1].id, "ts/16");
    EXPECT_EQ(ref.series[2].id, "cs/16");
    EXPECT_EQ(ref.series[1].tile, 16u);
    EXPECT_EQ(ref.series[0].light_file, "10#1x_1y_1z.json");
    EXPECT_EQ(ref.series[0].width, 32u);
    EXPECT_EQ(ref.series[1].counts.at(2), 2500.0);
    ASSERT_EQ(ref.notes.size(), 1u);
    EXPECT_NE(ref.notes[0].find("cs/64"), std::string::npos);
  }
  EXPECT_THROW(loadThesisReference(test::tempDir(), ""), UserError);
  EXPECT_THROW(loadThesisReference(root, "other-scene"), UserError);
  test::writeText(fs::path(root) / "bad.json", "{\"frames\": [{\"frame\": 1}]}");
  EXPECT_THROW(readLcData(root + "/bad.json"), UserError);
}

TEST(BenchCompareReference, ComparesOursWithTheirs) {
  const std::string suite = test::writeSmallSuite(test::tempDir() + "/ref-suites");
  const std::string root = writeReference(test::tempDir() + "/ref-run", "small-scene");
  const std::string out = test::tempDir() + "/ref-out";
  auto r = runManylights("compare-reference --reference " + root + " --suite " + suite + " --json " + out +
                         "/c.json --csv " + out + "/c.csv --markdown " + out + "/c.md --progress none");
  ASSERT_EQ(r.exit_code, 0) << r.err << r.out;
  EXPECT_NE(r.out.find("note: cs/64"), std::string::npos) << r.out;
  if (!registered("clustered-deferred")) {
    EXPECT_NE(r.out.find("skipped cs/16: technique 'clustered-deferred' is not registered"), std::string::npos)
        << r.out;
  }

  std::ifstream in(out + "/c.json");
  const auto j = nlohmann::json::parse(in);
  EXPECT_EQ(j["naive_scale"], 10.0);
  const auto& ns = j["series"][0];
  ASSERT_EQ(ns["series"], "ns");
  ASSERT_EQ(ns["frames"].size(), 3u);
  for (int i = 0; i < 3; ++i) {
    EXPECT_EQ(ns["covered_pixels"][i], 1024.0);
    EXPECT_EQ(ns["ours"][i], 10240.0);  // every light for every covered pixel
    EXPECT_EQ(ns["thesis"][i], 10240.0);
    EXPECT_EQ(ns["thesis_raw"][i], 1024.0);
  }
  EXPECT_DOUBLE_EQ(ns["ratio"]["mean"].get<double>(), 1.0);
  EXPECT_EQ(j["matched_frames"].size(), 3u);

  const auto& ts = j["series"][1];
  ASSERT_EQ(ts["series"], "ts/16");
  if (registered("tiled-deferred")) {
    ASSERT_EQ(ts["ours"].size(), 3u);
    EXPECT_NE(ts["label"].get<std::string>().find("tile=16"), std::string::npos);
    EXPECT_NE(ts["label"].get<std::string>().find("tile_depth=none"), std::string::npos);
    for (int i = 0; i < 3; ++i) {
      EXPECT_GE(ts["ours"][i].get<double>(), ts["lower_bound"][i].get<double>());
      EXPECT_LE(ts["ours"][i].get<double>(), 10240.0);
    }
    bool found = false;
    for (const auto& row : j["ratios"])
      if (row["ratio"] == "tiled/naive" && row["tile"] == 16) {
        found = true;
        EXPECT_NEAR(row["thesis"]["mean"].get<double>(), (5000.0 + 5000.0 + 2500.0) / 3 / 10240.0, 1e-9);
        EXPECT_NEAR(row["thesis"]["median"].get<double>(), 5000.0 / 10240.0, 1e-9);
      }
    EXPECT_TRUE(found) << j["ratios"].dump();
  } else {
    EXPECT_TRUE(ts.contains("skipped"));
  }
  std::ifstream md(out + "/c.md");
  std::stringstream mds;
  mds << md.rdbuf();
  EXPECT_NE(mds.str().find("| ns |"), std::string::npos) << mds.str();
  EXPECT_TRUE(fs::is_regular_file(out + "/c.csv"));

  // Selecting only what is not there is an error, not an empty report.
  auto none = runManylights("compare-reference --reference " + root + " --suite " + suite + " --tiles 8 --techniques "
                            "tiled-deferred --progress none");
  EXPECT_EQ(none.exit_code, 2) << none.out;
  auto bad = runManylights("compare-reference --reference " + test::tempDir() + " --suite " + suite);
  EXPECT_EQ(bad.exit_code, 2);
  EXPECT_NE(bad.err.find("--reference"), std::string::npos) << bad.err;
}

}  // namespace
}  // namespace ml
