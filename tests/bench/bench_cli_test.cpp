// `manylights bench` as a researcher runs it: a two-frame run of every
// registered technique on the project's own scene (JSON/CSV schema, counts
// that respect the exact lower bound), a sweep over a small generated suite
// (light sets x sizes x parameters), plots, and one-line errors.
#include "ml_test_paths.h"  // MANYLIGHTS_TEST_DATA_DIR, MANYLIGHTS_BINARY (generated)
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>

#include "host/app/BenchCommand.hpp"
#include "host/techniques/Registry.hpp"
#include "suite/suite_support.hpp"
#include "support/RunCommand.hpp"

namespace ml {
namespace {

using test::lines;
using test::readJson;
using test::runManylights;

// The techniques of the `manylights` binary (not those the test binary adds).
std::string allTechniques() {
  std::string s;
  for (const auto& t : techniques())
    if (t.built_in) s += (s.empty() ? "" : ",") + t.name;
  return s;
}

bool registered(const std::string& name) {
  for (const auto& t : techniques())
    if (t.name == name) return true;
  return false;
}

void expectUserError(const test::CommandResult& r, const std::string& must_mention) {
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find(must_mention), std::string::npos) << "expected '" << must_mention << "' in: " << r.err;
  EXPECT_EQ(lines(r.err), 1) << r.err;
}

const std::string& smallSuite() {
  static const std::string dir = test::writeSmallSuite(test::tempDir() + "/bench-suites");
  return dir;
}

TEST(BenchCli, TwoFramesOfEveryRegisteredTechnique) {
  const std::string dir = test::tempDir() + "/bench-all";
  const std::string json = dir + "/b.json", csv = dir + "/b.csv";
  auto r = runManylights("bench --techniques " + allTechniques() + " --lights 64 --size 64x48 --frames 0:1 --json " +
                         json + " --csv " + csv + " --progress lines");
  ASSERT_EQ(r.exit_code, 0) << r.err << r.out;
  EXPECT_NE(r.err.find("progress:"), std::string::npos) << r.err;
  EXPECT_NE(r.out.find("light evaluations per frame"), std::string::npos) << r.out;

  const auto j = readJson(json);
  EXPECT_EQ(j["schema"], "manylights-bench/1");
  EXPECT_EQ(j["meta"]["frames"], nlohmann::json({0, 1}));
  const std::size_t n_tech = std::count_if(techniques().begin(), techniques().end(), [](const TechniqueInfo& t) { return t.built_in; });
  ASSERT_EQ(j["records"].size(), 2 * n_tech);
  std::set<std::string> seen;
  for (const auto& rec : j["records"]) {
    const std::string tech = rec["technique"];
    seen.insert(tech);
    SCOPED_TRACE(tech);
    EXPECT_TRUE(rec["frame"] == 0 || rec["frame"] == 1);
    EXPECT_EQ(rec["width"], 64);
    EXPECT_EQ(rec["height"], 48);
    EXPECT_EQ(rec["light_count"], 64);
    const auto evals = rec["light_evaluations"].get<std::uint64_t>();
    const auto bound = rec["lower_bound"].get<std::uint64_t>();
    const auto covered = rec["covered_pixels"].get<std::uint64_t>();
    EXPECT_GT(covered, 0u);
    EXPECT_GE(evals, bound) << "light lists must be conservative";
    EXPECT_LE(evals, 64u * covered);
    if (tech == "forward" || tech == "deferred") {
      EXPECT_EQ(evals, 64u * covered);
    }
    ASSERT_TRUE(rec["passes"].is_object());
    EXPECT_FALSE(rec["passes"].empty());
    for (const auto& [name, ms] : rec["passes"].items()) EXPECT_GE(ms.get<double>(), 0.0) << name;
    EXPECT_TRUE(rec["memory_bytes"].is_number_unsigned());
    EXPECT_GT(rec["host_ms"].get<double>(), 0.0);
  }
  EXPECT_EQ(seen.size(), n_tech);
  ASSERT_EQ(j["summaries"].size(), n_tech);
  for (const auto& s : j["summaries"]) {
    EXPECT_EQ(s["frames"], 2);
    for (const char* k : {"light_evaluations", "lower_bound", "passes_total_ms"})
      for (const char* stat : {"mean", "median", "p95", "max"}) EXPECT_TRUE(s[k][stat].is_number()) << k << stat;
  }

  std::ifstream in(csv);
  std::string header, line;
  std::getline(in, header);
  for (const char* col : {"technique", "frame", "light_evaluations", "lower_bound", "memory_bytes", "passes_total_ms"})
    EXPECT_NE(header.find(col), std::string::npos) << col;
  std::size_t rows = 0;
  while (std::getline(in, line)) ++rows;
  EXPECT_EQ(rows, 2 * n_tech);
}

TEST(BenchCli, SweepsLightSetsSizesAndParametersOnASuite) {
  const std::string json = test::tempDir() + "/bench-sweep.json";
  std::string techs = "deferred";
  if (registered("tiled-deferred")) techs += ",tiled-deferred";
  auto r = runManylights("bench --suite " + smallSuite() + " --lights thesis --sizes 32x32,48x32 --techniques " +
                         techs + " --param tile=8,16 --frames 0:2:2 --no-timing --json " + json + " --progress none");
  ASSERT_EQ(r.exit_code, 0) << r.err << r.out;
  const auto j = readJson(json);
  EXPECT_EQ(j["meta"]["scene"]["format"], "ntiled-suite");
  EXPECT_EQ(j["meta"]["camera"]["fovy"], 45.0);
  const std::size_t variants = registered("tiled-deferred") ? 3 : 1;
  ASSERT_EQ(j["records"].size(), 2 /*sizes*/ * 2 /*light sets*/ * variants * 2 /*frames*/);
  std::set<std::string> lights, sizes, labels;
  for (const auto& rec : j["records"]) {
    lights.insert(rec["lights"].get<std::string>() + "/" + std::to_string(rec["light_count"].get<int>()));
    sizes.insert(std::to_string(rec["width"].get<int>()) + "x" + std::to_string(rec["height"].get<int>()));
    labels.insert(rec["run"].get<std::string>().substr(0, rec["run"].get<std::string>().find(' ')));
    EXPECT_TRUE(rec["passes"].empty());
    EXPECT_TRUE(rec["passes_total_ms"].is_null());
    // The wall fills every frame: every pixel is covered.
    EXPECT_EQ(rec["covered_pixels"], rec["width"].get<int>() * rec["height"].get<int>());
  }
  EXPECT_EQ(lights, (std::set<std::string>{"10#1x_1y_1z/10", "20#2x_1y_1z/20"}));
  EXPECT_EQ(sizes, (std::set<std::string>{"32x32", "48x32"}));
  if (registered("tiled-deferred")) {
    EXPECT_TRUE(labels.count("tiled-deferred[tile=8]"));
    EXPECT_TRUE(labels.count("tiled-deferred[tile=16]"));
  }
  EXPECT_TRUE(labels.count("deferred"));
}

TEST(BenchCli, ResampledPathAndGltfFile) {
  const std::string json = test::tempDir() + "/bench-resample.json";
  auto r = runManylights("bench --suite " + smallSuite() + " --lights 10#1x_1y_1z --resample 5 --frames 1:3:2 "
                         "--techniques deferred --size 24x24 --no-counts --repeat 2 --json " + json +
                         " --progress none");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = readJson(json);
  EXPECT_EQ(j["meta"]["camera"]["path_frames"], 5);
  ASSERT_EQ(j["records"].size(), 2u);
  EXPECT_TRUE(j["records"][0]["light_evaluations"].is_null());
  EXPECT_FALSE(j["records"][0]["passes"].empty());

  const std::string glb = std::string(MANYLIGHTS_TEST_DATA_DIR) + "/default/scene.glb";
  const std::string cam = std::string(MANYLIGHTS_TEST_DATA_DIR) + "/default/camera.json";
  r = runManylights("bench --suite " + glb + " --camera " + cam + " --lights 32 --techniques forward --size 32x32 "
                    "--frames 0 --no-timing --progress none");
  EXPECT_EQ(r.exit_code, 0) << r.err;
  expectUserError(runManylights("bench --suite " + glb + " --lights 32 --techniques forward --size 32x32"), "--camera");
}

TEST(BenchCli, ErrorsAreOneLineNamingTheFlagOrFile) {
  const std::string missing = test::writeSmallSuite(test::tempDir() + "/bench-suites", "with-missing", true);
  expectUserError(runManylights("bench --suite " + missing + " --techniques deferred --size 16x16 --frames 0"),
                  "Gone.obj");
  auto ok = runManylights("bench --suite " + missing + " --allow-missing-meshes --techniques deferred --size 16x16 "
                          "--frames 0 --progress none");
  EXPECT_EQ(ok.exit_code, 0) << ok.err;
  EXPECT_NE((ok.out + ok.err).find("Gone"), std::string::npos) << "expected a warning naming the missing mesh";
  EXPECT_NE(ok.out.find("missing meshes (skipped): Gone"), std::string::npos) << ok.out;

  const std::string s = smallSuite();
  expectUserError(runManylights("bench --suite " + s + " --techniques deferred --frames 7:"), "--frames");
  expectUserError(runManylights("bench --suite " + s + " --techniques deferred --frames 2:1"), "--frames");
  expectUserError(runManylights("bench --suite " + s + " --techniques nope"), "--techniques");
  expectUserError(runManylights("bench --suite " + s + " --techniques deferred --param tile=zero"), "--param");
  expectUserError(runManylights("bench --suite " + s + " --techniques deferred --param bogus=1"), "--param");
  expectUserError(runManylights("bench --suite " + s + " --techniques deferred --lights 999"), "--lights");
  expectUserError(runManylights("bench --suite " + s + " --techniques deferred --lights nosuch.json"), "--lights");
  expectUserError(runManylights("bench --suite " + s + " --sizes 32x32,big"), "--sizes");
  expectUserError(runManylights("bench --suite /no/such/dir"), "/no/such/dir");
  expectUserError(runManylights("bench --suite " + s + " --techniques deferred --plot " + test::tempDir() + "/p",
                                "MANYLIGHTS_PYTHON=/nonexistent/python3"),
                  "python3-matplotlib");
}

TEST(BenchCli, PlotsAreWritten) {
  if (findPlotPython().empty()) GTEST_SKIP() << "no python3 with matplotlib (python3-matplotlib); plots not tested";
  namespace fs = std::filesystem;
  const std::string dir = test::tempDir() + "/bench-plots";
  auto r = runManylights("bench --suite " + smallSuite() + " --lights thesis --techniques deferred --sizes "
                         "24x24,32x32 --frames 0:2 --plot " + dir + " --progress none");
  ASSERT_EQ(r.exit_code, 0) << r.err << r.out;
  EXPECT_TRUE(fs::is_regular_file(dir + "/bench.json"));
  std::size_t pngs = 0;
  for (const auto& e : fs::directory_iterator(dir)) pngs += e.path().extension() == ".png";
  EXPECT_GE(pngs, 3u) << "per-frame series, mean vs lights, mean vs resolution";
  EXPECT_TRUE(fs::is_regular_file(dir + "/frames_light_evaluations.png"));
  EXPECT_TRUE(fs::is_regular_file(dir + "/mean_vs_lights.png"));
  EXPECT_TRUE(fs::is_regular_file(dir + "/mean_vs_resolution.png"));
}

}  // namespace
}  // namespace ml
