// `render --gi vct --revoxelize` (moving geometry) as users run it, this
// build's binary on the default scene at 16^3 voxels:
//  - with the flag every timed frame voxelizes (vct_voxelizations equals
//    vct_updates in the stats JSON, `vct-voxelize` has a non-zero median) and
//    every frame still injects, filters and unpacks; without it (the lights
//    do not move either) only the first frame updates and voxelizes, the two
//    others reuse the volume (vct_reused; medians of zero over three frames);
//  - the geometry does not move, so the re-voxelized volume is the first one:
//    the frame and the indirect image are equal bit for bit (the voxel sums
//    are integers and the passes deterministic).
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <cstring>
#include <string>
#include <vector>

#include "host/util/ImageIO.hpp"
#include "support/RunCommand.hpp"
#include "support/TempDir.hpp"

namespace ml {
namespace {

struct VctRun {
  nlohmann::json stats;
  std::string frame, indirect;  // the .exr files
};

VctRun renderVct(const test::TempDir& tmp, const std::string& name, const std::string& extra) {
  VctRun run{nullptr, tmp.file(name + ".exr"), tmp.file(name + "_gi_vct.exr")};
  const std::string stats = tmp.file(name + ".json");
  const auto r = test::runManylights("render --size 64x40 --lights 64 --technique tiled-deferred --frames 3 "
                                     "--warmup 0 --gi vct --voxels 16 --levels 3 --out " + run.frame +
                                     " --stats-json " + stats + extra);
  EXPECT_EQ(r.exit_code, 0) << r.out << r.err;
  if (r.exit_code == 0) run.stats = test::readJson(stats);
  return run;
}

// "" when both images have the same size and the same floats, else where not.
std::string firstDifference(const std::string& a, const std::string& b) {
  unsigned wa = 0, ha = 0, wb = 0, hb = 0;
  const std::vector<float> ia = readImageRgba(a, wa, ha), ib = readImageRgba(b, wb, hb);
  if (wa != wb || ha != hb) return "sizes differ";
  for (std::size_t i = 0; i < ia.size(); ++i)
    if (std::memcmp(&ia[i], &ib[i], sizeof(float)) != 0)
      return "pixel " + std::to_string(i / 4) + " channel " + std::to_string(i % 4) + ": " + std::to_string(ia[i]) +
             " vs " + std::to_string(ib[i]);
  return "";
}

bool nonZero(const std::vector<float>& rgba) {
  for (std::size_t i = 0; i < rgba.size(); i += 4)
    if (rgba[i] > 0 || rgba[i + 1] > 0 || rgba[i + 2] > 0) return true;
  return false;
}

TEST(VctRevoxelize, EveryFrameVoxelizesAndTheImageIsTheStaticOne) {
  test::TempDir tmp;
  const VctRun once = renderVct(tmp, "once", "");
  const VctRun every = renderVct(tmp, "every", " --revoxelize");
  ASSERT_FALSE(once.stats.is_null());
  ASSERT_FALSE(every.stats.is_null());

  EXPECT_EQ(every.stats.at("gi_vct").at("revoxelize"), true);
  EXPECT_EQ(every.stats.at("vct_updates"), 3);
  EXPECT_EQ(every.stats.at("vct_voxelizations"), 3);
  EXPECT_EQ(every.stats.at("vct_reused"), 0);
  const auto& passes = every.stats.at("passes");
  // Medians over the three frames: non-zero only if (at least) two of them ran the pass.
  for (const char* pass : {"vct-voxelize", "vct-inject", "vct-mips", "vct-textures", "vct-trace"})
    EXPECT_GT(passes.value(pass, 0.0), 0.0) << pass << " did not run on every frame with --revoxelize";

  EXPECT_EQ(once.stats.at("gi_vct").at("revoxelize"), false);
  EXPECT_EQ(once.stats.at("vct_updates"), 1);
  EXPECT_EQ(once.stats.at("vct_voxelizations"), 1);
  EXPECT_EQ(once.stats.at("vct_reused"), 2);
  for (const char* pass : {"vct-voxelize", "vct-inject", "vct-mips", "vct-textures"})
    EXPECT_EQ(once.stats.at("passes").value(pass, -1.0), 0.0) << pass << ": ran after frame 1 with static lights";
  EXPECT_GT(once.stats.at("passes").value("vct-trace", 0.0), 0.0);

  unsigned w = 0, h = 0;
  ASSERT_TRUE(nonZero(readImageRgba(once.indirect, w, h))) << "no indirect light: equal images would prove nothing";
  EXPECT_EQ(firstDifference(once.indirect, every.indirect), "") << "indirect image";
  EXPECT_EQ(firstDifference(once.frame, every.frame), "") << "frame";
}

// A switch flag given a value takes the table's words (on|off|true|false|1|0):
// --KEY=off turns it off, anything else is one line naming the flag, exit 2
// (CLI11 used to abort on an unknown word and to read every value as on).
TEST(VctRevoxelize, SwitchFlagValuesAreTheTablesWords) {
  for (const char* flag : {"--revoxelize", "--anisotropic", "--specular"}) {
    const auto r = test::runManylights("render --size 16x16 --gi vct --voxels 16 " + std::string(flag) + "=maybe");
    EXPECT_EQ(r.exit_code, 2) << flag << ": " << r.err;
    EXPECT_EQ(test::lines(r.err), 1) << r.err;
    EXPECT_NE(r.err.find(std::string(flag) + ": expected on|off, got 'maybe'"), std::string::npos) << r.err;
  }
  test::TempDir tmp;
  const std::string stats = tmp.file("s.json");
  const auto r = test::runManylights("render --size 16x16 --lights 8 --frames 2 --warmup 0 --gi vct --voxels 16 "
                                     "--revoxelize=off --specular=1 --anisotropic --stats-json " + stats);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = test::readJson(stats);
  EXPECT_EQ(j.at("gi_vct").at("revoxelize"), false);
  EXPECT_EQ(j.at("gi_vct").at("specular"), true);
  EXPECT_EQ(j.at("gi_vct").at("anisotropic"), true);
  EXPECT_EQ(j.at("vct_voxelizations"), 1);
}

}  // namespace
}  // namespace ml
