// ViewerGi (the viewer's global illumination state): settings go through the
// VCT settings table and checkVctGiSettings as render's flags do; a refused
// value (bad text, out of range, unknown key, bad mode or voxel view, a level
// at or beyond --levels) throws UserError naming the flag and leaves the
// pass and the settings as they were; a --levels change pulls the shown voxel
// level down with it.
#include <gtest/gtest.h>

#include <functional>
#include <random>
#include <string>

#include "host/util/Error.hpp"
#include "host/vct/VctSettingsTable.hpp"
#include "host/view/ViewerGi.hpp"
#include "support/RandomSoup.hpp"
#include "support/TestDevice.hpp"
#include "support/TestGl.hpp"

namespace ml {
namespace {

void expectRefused(const std::function<void()>& action, const std::string& mention) {
  try {
    action();
    ADD_FAILURE() << "accepted; expected a refusal naming " << mention;
  } catch (const UserError& e) {
    EXPECT_NE(std::string(e.what()).find(mention), std::string::npos) << e.what();
  }
}

TEST(ViewerGi, RefusedValuesKeepTheLastWorkingState) {
  test::glContext();
  ViewerGi gi(test::runtime(), Aabb{glm::vec3(-1), glm::vec3(1)});
  EXPECT_FALSE(gi.on());
  gi.setParam("voxels", "16");  // accepted while off: used when turned on
  gi.setMode("vct");
  ASSERT_TRUE(gi.on());
  EXPECT_EQ(gi.settings().grid.voxels, 16u);
  gi.setVoxelLevel(3);
  const GiPass* before = gi.pass();
  expectRefused([&] { gi.setParam("voxels", "33"); }, "--voxels");
  expectRefused([&] { gi.setParam("voxels", "sixteen"); }, "--voxels");
  expectRefused([&] { gi.setParam("levels", "6"); }, "--levels");
  expectRefused([&] { gi.setParam("cone-aperture", "180"); }, "--cone-aperture");
  expectRefused([&] { gi.setParam("gi-scale", "0"); }, "--gi-scale");
  expectRefused([&] { gi.setParam("vct-shadows", "ray"); }, "--vct-shadows");
  expectRefused([&] { gi.setParam("anisotropic", "maybe"); }, "--anisotropic");
  expectRefused([&] { gi.setParam("revoxelize", "sometimes"); }, "--revoxelize");
  expectRefused([&] { gi.setParam("bogus", "1"); }, "bogus");
  expectRefused([&] { gi.setMode("path-tracing"); }, "gi");
  expectRefused([&] { gi.setVoxelView("normals"); }, "--voxel-view");
  expectRefused([&] { gi.setVoxelLevel(5); }, "--voxel-level");
  EXPECT_EQ(gi.pass(), before) << "a refused value rebuilt the pass";
  EXPECT_EQ(gi.settings().grid.voxels, 16u);
  EXPECT_EQ(gi.settings().grid.levels, 4u);
  EXPECT_EQ(gi.voxelLevel(), 3u);
  gi.setParam("levels", "2");
  EXPECT_NE(gi.pass(), before) << "an accepted value keeps the old pass";
  EXPECT_EQ(gi.voxelLevel(), 1u) << "the voxel level follows --levels down";
  gi.setMode("none");
  EXPECT_FALSE(gi.on());
  EXPECT_EQ(gi.settings().grid.levels, 2u) << "turning VCT off keeps its settings";
}

TEST(ViewerGi, TheTableCoversEverySettingWithItsDefault) {
  const vct::VctGiSettings defaults;
  for (const vct::VctSetting& s : vct::vctSettings()) {
    SCOPED_TRACE(s.key);
    // Each default reads back and parses to itself: the table and the struct agree.
    const vct::VctGiSettings again = vct::withVctSetting(defaults, s.key, s.get(defaults));
    EXPECT_EQ(s.get(again), s.get(defaults));
  }
  EXPECT_EQ(vct::vctSettings().size(), 9u) << "a VCT setting was added: give it a row (and the viewer gets it)";
}

// gi_param revoxelize (the panel's checkbox) reaches the pipeline: with it
// every frame updates and voxelizes, without it only the first (the lights
// keep their version, so the later frames reuse the volume); the pass is
// rebuilt either way, so each setting starts from its own first voxelization.
TEST(ViewerGi, RevoxelizeReachesThePipeline) {
  test::glContext();
  const std::uint64_t seed = test::freshSeed();
  SCOPED_TRACE("seed=" + std::to_string(seed));
  std::mt19937_64 rng(seed);
  const Scene scene = test::randomSoup(rng, 12);
  const auto lights = test::randomLightsIn(rng, 5, scene.bounds);
  SceneGpu gpu_scene(scene);
  ViewerGi gi(test::runtime(), scene.bounds);
  gi.setParam("voxels", "8");
  gi.setMode("vct");
  for (const char* value : {"1", "0", "on"}) {
    SCOPED_TRACE(std::string("revoxelize ") + value);
    gi.setParam("revoxelize", value);
    const bool on = std::string(value) != "0";
    EXPECT_EQ(gi.settings().revoxelize, on);
    auto* pass = dynamic_cast<vct::VctGiPass*>(gi.pass());
    ASSERT_NE(pass, nullptr);
    for (int frame = 0; frame < 3; ++frame) {
      PassTimings t;
      pass->update({gpu_scene, lights, t, /*lights_version=*/1});
      bool voxelized = false;
      for (const auto& e : t.entries()) voxelized |= e.first == "vct-voxelize";
      EXPECT_EQ(voxelized, on || frame == 0) << "frame " << frame;
    }
    EXPECT_EQ(pass->pipeline().voxelizations(), on ? 3u : 1u);
    EXPECT_EQ(pass->volumeUpdates(), on ? 3u : 1u);
    EXPECT_EQ(pass->volumeReuses(), on ? 0u : 2u);
  }
}

}  // namespace
}  // namespace ml
