// `manylights view` with voxel cone tracing, under Xvfb: a scripted session
// turns gi vct on with settings by key (the same table as render's flags),
// and its shaded frame, its "indirect" view and its "voxels" view (a fresh
// random kind and level) and its albedo slice of that level (a random
// vertical plane) equal `render --gi vct` of the same camera: the frame,
// <out>_gi_vct.png, <out>_gi_vct_voxels.png and (--voxel-slice)
// <out>_gi_vct_slice.png, within the render tests' tolerance
// (expectSameImage); with gi_param revoxelize its frame equals render's with
// and without --revoxelize. Refused values name the action and the flag, exit 2.
#include <gtest/gtest.h>

#include <filesystem>
#include <random>
#include <string>

#include "view_support.hpp"

namespace ml {
namespace {

using nlohmann::json;

TEST(ViewVct, FrameIndirectAndVoxelViewsEqualRender) {
  if (!test::haveXvfb()) GTEST_SKIP() << "xvfb-run is missing (Debian package xvfb): the viewer cannot be tested";
  const std::string dir = test::tempDir() + "/view_vct";
  std::filesystem::create_directories(dir);
  const unsigned seed = std::random_device{}();
  std::printf("view vct test seed %u\n", seed);
  std::mt19937 rng(seed);
  const char* kinds[] = {"albedo", "radiance", "opacity"};
  const std::string kind = kinds[rng() % 3];
  // Level 0's opacity is 1 wherever a surface is, and from inside the default
  // scene's rooms level 2's 8^3 voxels can all read the same opacity: flat
  // images, which expectSameImage refuses. Opacity at level 1, the others at 0 or 1.
  const unsigned level = kind == std::string("opacity") ? 1 : rng() % 2;
  const float yaw = std::uniform_real_distribution<float>(-30.0f, 30.0f)(rng);
  // The slice shows albedo on a vertical plane through the middle: it cuts
  // the floors and walls (a horizontal plane can lie between floors, and the
  // radiance of a plane can be nearly all dark: flat images).
  const std::string slice = std::string(1, "xz"[rng() % 2]) + ":" +
                            std::to_string(std::uniform_real_distribution<float>(0.3f, 0.7f)(rng));
  SCOPED_TRACE("voxel view " + kind + " level " + std::to_string(level) + " yaw " + std::to_string(yaw) + " slice " +
               slice);
  const json script = json::array(
      {{{"technique", "tiled-deferred"}}, {{"orbit", {yaw, 0.0}}}, {{"record", "start"}}, {{"gi", "vct"}},
       {{"gi_param", {{"voxels", "32"}, {"levels", "3"}}}}, {{"wait", 1}}, {{"screenshot", dir + "/view.png"}},
       {{"view", "indirect"}}, {{"wait", 1}}, {{"screenshot", dir + "/view_indirect.png"}},
       {{"voxel_view", kind}}, {{"voxel_level", level}}, {{"view", "voxels"}}, {{"wait", 1}},
       {{"screenshot", dir + "/view_voxels.png"}}, {{"voxel_view", "albedo"}}, {{"voxel_slice", slice}}, {{"wait", 1}},
       {{"screenshot", dir + "/view_slice.png"}}, {{"record_save", dir + "/camera.json"}}});
  const test::CommandResult v = test::runViewScript(script, "vct");
  ASSERT_EQ(v.exit_code, 0) << v.out << v.err;
  const std::string render = "render --technique tiled-deferred " + std::string(test::kViewFrame) + " --camera " +
                             dir + "/camera.json --frames 1 --gi vct --voxels 32 --levels 3 --voxel-level " +
                             std::to_string(level) + " --voxel-view ";
  const auto r = test::runManylights(render + kind + " --out " + dir + "/render.png");
  ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
  const auto rs = test::runManylights(render + "albedo --voxel-slice " + slice + " --out " + dir + "/render_s.png");
  ASSERT_EQ(rs.exit_code, 0) << rs.out << rs.err;
  test::expectSameImage(dir + "/view.png", dir + "/render.png");
  test::expectSameImage(dir + "/view_indirect.png", dir + "/render_gi_vct.png");
  test::expectSameImage(dir + "/view_voxels.png", dir + "/render_gi_vct_voxels.png");
  test::expectSameImage(dir + "/view_slice.png", dir + "/render_s_gi_vct_slice.png");
}

// gi_param revoxelize: the viewer re-voxelizes every frame, and its frame
// equals render's, with --revoxelize and without (the geometry is static:
// the same volume).
TEST(ViewVct, RevoxelizingFrameEqualsRender) {
  if (!test::haveXvfb()) GTEST_SKIP() << "xvfb-run is missing (Debian package xvfb): the viewer cannot be tested";
  const std::string dir = test::tempDir() + "/view_vct_revox";
  std::filesystem::create_directories(dir);
  const json script = json::array({{{"technique", "tiled-deferred"}}, {{"record", "start"}}, {{"gi", "vct"}},
                                   {{"gi_param", {{"voxels", "16"}, {"levels", "3"}, {"revoxelize", "1"}}}},
                                   {{"wait", 3}}, {{"screenshot", dir + "/view.png"}},
                                   {{"record_save", dir + "/camera.json"}}});
  const test::CommandResult v = test::runViewScript(script, "vct_revox");
  ASSERT_EQ(v.exit_code, 0) << v.out << v.err;
  const std::string render = "render --technique tiled-deferred " + std::string(test::kViewFrame) + " --camera " +
                             dir + "/camera.json --frames 2 --gi vct --voxels 16 --levels 3 --out " + dir;
  for (const char* flag : {" --revoxelize", ""}) {
    const std::string out = std::string("/render") + (*flag ? "_revox" : "") + ".png";
    const auto r = test::runManylights(render + out + flag);
    ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
    test::expectSameImage(dir + "/view.png", dir + out);
  }
}

// Every refused value is checked in-process (ViewerGi.RefusedValuesKeepTheLastWorkingState);
// here the script's error names the action and the flag and the viewer exits 2,
// once for a GI parameter and once for a GI view verb (each run starts a viewer).
TEST(ViewVct, RefusedSettingsNameTheActionAndTheFlag) {
  if (!test::haveXvfb()) GTEST_SKIP() << "xvfb-run is missing (Debian package xvfb): the viewer cannot be tested";
  struct Case {
    json action;
    std::string mention;
  };
  const Case cases[] = {{{{"gi_param", {{"voxels", "33"}}}}, "--voxels"}, {{{"voxel_slice", "w:0.5"}}, "--voxel-slice"}};
  for (const Case& c : cases) {
    SCOPED_TRACE(c.action.dump());
    const auto r = test::runViewScript(json::array({{{"gi", "vct"}}, {{"wait", 1}}, c.action}), "vct_refused");
    EXPECT_EQ(r.exit_code, 2) << r.out << r.err;
    EXPECT_NE(r.err.find("action 2"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find(c.mention), std::string::npos) << r.err;
  }
}

}  // namespace
}  // namespace ml
