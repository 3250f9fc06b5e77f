// `manylights bench --gi vct`: the VCT settings as a sweep dimension (--param
// keys resolved against the VCT settings table), the records' GI fields in
// JSON and CSV, one-line errors before any frame, and gi_rel_rmse equal to
// `render --gi vct --gi-reference` of the same frame and settings.
#include "ml_test_paths.h"  // MANYLIGHTS_TEST_DATA_DIR, MANYLIGHTS_BINARY (generated)
#include <gtest/gtest.h>

#include <cmath>

#include <nlohmann/json.hpp>

#include <fstream>
#include <set>
#include <sstream>
#include <string>

#include "support/RunCommand.hpp"
#include "support/TempDir.hpp"

namespace ml {
namespace {

using test::lines;
using test::readJson;

// The Cornell box with its 4 lights, one frame, one technique: small enough to sweep.
std::string cornellBench(const std::string& size = "48x32", unsigned warmup = 0) {
  const std::string dir = std::string(MANYLIGHTS_TEST_DATA_DIR) + "/cornell/";
  return "bench --scene " + dir + "cornell.gltf --lights " + dir + "lights.json --camera " + dir +
         "camera.json --techniques deferred --size " + size + " --frames 0 --warmup " + std::to_string(warmup) +
         " --progress none ";
}

TEST(BenchGi, SweepOfTwoVctKeysGivesFourRecordsWithTheirSettingsAndPasses) {
  test::TempDir tmp;
  const std::string json = tmp.file("b.json"), csv = tmp.file("b.csv");
  const auto r = test::runManylights(cornellBench() + "--gi vct --param voxels=16,32 --param cones=5,9 --no-counts "
                                     "--json " + json + " --csv " + csv);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto recs = readJson(json).at("records");
  ASSERT_EQ(recs.size(), 4u);
  std::set<std::pair<std::string, std::string>> seen;
  std::set<std::size_t> bytes;
  std::set<std::string> runs;
  for (const auto& rec : recs) {
    EXPECT_EQ(rec.at("gi"), "vct");
    const auto& s = rec.at("gi_settings");
    seen.emplace(s.at("voxels").get<std::string>(), s.at("cones").get<std::string>());
    EXPECT_EQ(s.at("levels"), "auto");  // the unswept settings keep the table's defaults
    for (const char* pass : {"vct-voxelize", "vct-inject", "vct-mips", "vct-trace", "vct-upsample"})
      EXPECT_TRUE(rec.at("passes").contains(pass)) << pass;
    bytes.insert(rec.at("voxel_bytes").get<std::size_t>());
    EXPECT_TRUE(rec.at("gi_rel_rmse").is_null());  // no --gi-reference
    EXPECT_EQ(rec.at("gi_updates"), 1);  // no warm-up: the one timed frame is the first
    EXPECT_EQ(rec.at("gi_reused"), 0);
    runs.insert(rec.at("run").get<std::string>());
  }
  const std::set<std::pair<std::string, std::string>> want = {{"16", "5"}, {"16", "9"}, {"32", "5"}, {"32", "9"}};
  EXPECT_EQ(seen, want);
  EXPECT_EQ(bytes.size(), 2u);  // one per voxel count
  EXPECT_EQ(runs.size(), 4u);   // each point is a run of its own
  EXPECT_EQ(readJson(json).at("summaries").size(), 4u);

  std::ifstream in(csv);
  std::string header, row;
  std::getline(in, header);
  EXPECT_NE(header.find(",gi,gi_settings,voxel_bytes,gi_rel_rmse,gi_ref_noise,gi_rel_rmse_corrected,gi_updates,gi_reused"), std::string::npos) << header;
  int rows = 0;
  while (std::getline(in, row)) {
    ++rows;
    EXPECT_NE(row.find("voxels="), std::string::npos) << row;
  }
  EXPECT_EQ(rows, 4);
}

// --param revoxelize=0,1 sweeps the table's switch: after one warm-up frame,
// the timed frames voxelize again only with revoxelize on (static geometry is
// voxelized once per run, in the warm-up). With static lights and revoxelize
// off the timed frames reuse the warm-up's volume (no vct-* update pass, the
// record's gi_updates says so); with --animate every timed frame updates.
TEST(BenchGi, RevoxelizeSweepVoxelizesOnlyWhereOn) {
  test::TempDir tmp;
  std::set<std::string> seen;
  for (const std::string animate : {"", "--animate 0.25 "}) {
    SCOPED_TRACE(animate);
    const std::string json = tmp.file("b.json");
    const auto r = test::runManylights(cornellBench("48x32", 1) + "--repeat 2 --gi vct --param voxels=16 "
                                       "--param revoxelize=0,1 --no-counts " + animate + "--json " + json);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const auto recs = readJson(json).at("records");
    ASSERT_EQ(recs.size(), 2u);
    for (const auto& rec : recs) {
      const std::string on = rec.at("gi_settings").at("revoxelize");
      seen.insert(on);
      const auto& passes = rec.at("passes");
      const bool updates = on == "on" || !animate.empty();
      EXPECT_EQ(rec.at("gi_updates"), updates ? 2 : 0) << "revoxelize " << on;
      EXPECT_EQ(rec.at("gi_reused"), updates ? 0 : 2) << "revoxelize " << on;
      for (const char* pass : {"vct-inject", "vct-mips", "vct-textures"})
        EXPECT_EQ(passes.value(pass, 0.0) > 0.0, updates) << pass << ", revoxelize " << on;
      EXPECT_GT(passes.value("vct-trace", 0.0), 0.0) << "revoxelize " << on;
      if (on == "on")
        EXPECT_GT(passes.value("vct-voxelize", 0.0), 0.0) << "revoxelize on: the timed frames voxelize";
      else
        EXPECT_FALSE(passes.contains("vct-voxelize")) << "revoxelize off: voxelized after the warm-up";
    }
  }
  EXPECT_EQ(seen, (std::set<std::string>{"off", "on"}));
}

// A key neither the technique's nor the GI's, a bad value, a GI key without
// --gi vct, and combinations that cannot be measured: one line, exit 2,
// before the devices open (nothing on stdout).
TEST(BenchGi, BadKeysAndValuesFailBeforeAnyFrame) {
  const std::string b = cornellBench() + "--gi vct ";
  struct Case {
    std::string args, mention;
  };
  for (const Case& c : std::vector<Case>{
           {b + "--param nosuch=1", "nosuch"},
           {b + "--param nosuch=1", "voxels"},  // names the GI keys too
           {b + "--param voxels=30", "--voxels"},
           {b + "--param voxels=32,48", "--voxels"},
           {b + "--param cones=abc", "--cones"},
           {b + "--param cone-aperture=0", "--cone-aperture"},
           {b + "--param voxels=16 --param levels=6", "--levels"},
           {b + "--param anisotropic=maybe", "--anisotropic"},
           {b + "--param revoxelize=2", "--revoxelize"},
           {cornellBench() + "--param voxels=32", "--gi vct"},
           {cornellBench() + "--gi sh", "--gi"},
           {cornellBench() + "--gi-reference", "--gi-reference"},
           {b + "--gi-reference --gi-samples 0", "--gi-samples"},
           {b + "--gi-reference --animate 0.5", "--gi-reference"},
           {b + "--no-timing", "--no-timing"},
           {b + "--no-shading", "--no-shading"},
       }) {
    const auto r = test::runManylights(c.args);
    EXPECT_EQ(r.exit_code, 2) << c.args << "\n" << r.err;
    EXPECT_NE(r.err.find(c.mention), std::string::npos) << c.args << "\n" << r.err;
    EXPECT_EQ(lines(r.err), 1) << c.args << "\n" << r.err;
    EXPECT_EQ(r.out, "") << c.args;
  }
}

// The bench's gi_rel_rmse is render's for the same frame, settings and
// reference samples; the reference is traced once and reused by both settings.
TEST(BenchGi, ReferenceErrorEqualsRendersOfTheSameFrameAndSettings) {
  test::TempDir tmp;
  const std::string dir = std::string(MANYLIGHTS_TEST_DATA_DIR) + "/cornell/";
  const std::string json = tmp.file("b.json");
  const auto b = test::runManylights(cornellBench("64x48") + "--gi vct --param anisotropic=off,on --param voxels=32 "
                                     "--gi-reference --gi-samples 8 --no-counts --repeat 1 --json " + json);
  ASSERT_EQ(b.exit_code, 0) << b.err;
  const auto recs = readJson(json).at("records");
  ASSERT_EQ(recs.size(), 2u);
  for (const auto& rec : recs) {
    const std::string aniso = rec.at("gi_settings").at("anisotropic");
    const std::string stats = tmp.file("r_" + aniso + ".json");
    const auto r = test::runManylights("render --scene " + dir + "cornell.gltf --lights " + dir + "lights.json --camera " +
                                       dir + "camera.json --technique deferred --size 64x48 --frame 0 --frames 1 "
                                       "--warmup 0 --gi vct --voxels 32 --anisotropic=" + aniso + " " +
                                       "--gi-reference --gi-samples 8 --stats-json " + stats);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const double want = readJson(stats).at("gi_rel_rmse").get<double>();
    ASSERT_FALSE(rec.at("gi_rel_rmse").is_null());
    EXPECT_GT(want, 0.0);
    EXPECT_NEAR(rec.at("gi_rel_rmse").get<double>(), want, 1e-4 * want) << "anisotropic " << aniso;
    // The reference's noise and the error without it: the same in both, and
    // the corrected error below the raw one (8 samples: a noisy reference).
    const double noise = readJson(stats).at("gi_ref_noise").get<double>();
    const double corrected = readJson(stats).at("gi_rel_rmse_corrected").get<double>();
    EXPECT_GT(noise, 0.0);
    EXPECT_LT(corrected, want);
    EXPECT_NEAR(corrected, std::sqrt(std::max(0.0, want * want - noise * noise)), 1e-6);
    EXPECT_NEAR(rec.at("gi_ref_noise").get<double>(), noise, 1e-4 * noise);
    EXPECT_NEAR(rec.at("gi_rel_rmse_corrected").get<double>(), corrected, 1e-4 * corrected + 1e-9);
  }
  EXPECT_NE(recs[0].at("gi_rel_rmse"), recs[1].at("gi_rel_rmse"));  // the settings do change the error
}

// Without --gi the records say so and have no GI fields filled.
TEST(BenchGi, WithoutGiRecordsSayNone) {
  test::TempDir tmp;
  const std::string json = tmp.file("b.json");
  const auto r = test::runManylights(cornellBench() + "--no-counts --json " + json);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto recs = readJson(json).at("records");
  ASSERT_EQ(recs.size(), 1u);
  EXPECT_EQ(recs[0].at("gi"), "none");
  EXPECT_TRUE(recs[0].at("gi_settings").empty());
  EXPECT_EQ(recs[0].at("voxel_bytes"), 0);
  EXPECT_TRUE(recs[0].at("gi_rel_rmse").is_null());
  EXPECT_TRUE(recs[0].at("gi_ref_noise").is_null());
  EXPECT_TRUE(recs[0].at("gi_rel_rmse_corrected").is_null());
  EXPECT_TRUE(recs[0].at("gi_updates").is_null());
  EXPECT_TRUE(recs[0].at("gi_reused").is_null());
  EXPECT_EQ(recs[0].at("run").get<std::string>().find("gi="), std::string::npos);
  for (const auto& [name, ms] : recs[0].at("passes").items()) EXPECT_NE(name.rfind("vct-", 0), 0u) << name;
}

}  // namespace
}  // namespace ml
