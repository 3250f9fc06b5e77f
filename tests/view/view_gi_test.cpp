// ViewerGi (the viewer's global illumination state): settings go through the
// VCT descriptor's ParamSpecs and checkVctGiSettings as render's flags do; a refused
// value (bad text, out of range, unknown key, bad mode or voxel view, a level
// at or beyond --levels) throws UserError naming the flag and leaves the
// pass and the settings as they were; a --levels change pulls the shown voxel
// level down with it.
#include <gtest/gtest.h>

#include <functional>
#include <random>
#include <string>

#include "host/util/Error.hpp"
#include "host/vct/VctGiDescriptor.hpp"
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
  Scene box;
  box.bounds = Aabb{glm::vec3(-1), glm::vec3(1)};
  ViewerGi gi(test::runtime(), box);
  EXPECT_FALSE(gi.on());
  gi.setParam("voxels", "16");  // accepted while off: used when turned on
  EXPECT_EQ(gi.params().text("levels"), "auto");
  gi.setParam("levels", "4");
  gi.setMode("vct");
  ASSERT_TRUE(gi.on());
  EXPECT_EQ(gi.params().text("voxels"), "16");
  gi.setView("voxel_level", "3");
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
  expectRefused([&] { gi.setView("voxel_view", "normals"); }, "--voxel-view");
  expectRefused([&] { gi.setView("voxel_level", "5"); }, "--voxel-level");
  expectRefused([&] { gi.setView("voxel_slice", "w:0.5"); }, "--voxel-slice");
  expectRefused([&] { gi.setView("voxel_slice", "z:2"); }, "--voxel-slice");
  EXPECT_EQ(gi.pass(), before) << "a refused value rebuilt the pass";
  EXPECT_EQ(gi.params().text("voxels"), "16");
  EXPECT_EQ(gi.params().text("levels"), "4");
  EXPECT_EQ(gi.view().count("voxel_level"), 3u);
  gi.setParam("levels", "2");
  EXPECT_NE(gi.pass(), before) << "an accepted value keeps the old pass";
  EXPECT_EQ(gi.view().count("voxel_level"), 1u) << "the voxel level follows --levels down";
  gi.setMode("none");
  EXPECT_FALSE(gi.on());
  EXPECT_EQ(gi.params().text("levels"), "2") << "turning VCT off keeps its settings";
}

// The descriptor's defaults are the settings struct's: a ParamSpec default
// that drifted from VctGiSettings would change what `--gi vct` renders.
TEST(ViewerGi, TheDescriptorDefaultsAreTheSettingsDefaults) {
  const vct::VctGiSettings want;
  const vct::VctGiSettings got = vct::vctSettingsOf(vct::giDescriptor().defaults());
  EXPECT_EQ(got.grid.voxels, want.grid.voxels);
  EXPECT_EQ(got.grid.levels, want.grid.levels);
  EXPECT_EQ(got.grid.anisotropic, want.grid.anisotropic);
  EXPECT_EQ(got.cones, want.cones);
  EXPECT_EQ(got.aperture_deg, want.aperture_deg);
  EXPECT_EQ(got.lod_bias, want.lod_bias);
  EXPECT_EQ(got.gi_scale, want.gi_scale);
  EXPECT_EQ(got.specular, want.specular);
  EXPECT_EQ(got.shadows, want.shadows);
  EXPECT_EQ(got.revoxelize, want.revoxelize);
  EXPECT_EQ(got.cascades, want.cascades);
  EXPECT_EQ(got.fold, want.fold);
  EXPECT_EQ(vct::giDescriptor().params.size(), 12u) << "a VCT setting was added: map it in vctSettingsOf";
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
  ViewerGi gi(test::runtime(), scene);
  gi.setParam("voxels", "8");
  gi.setMode("vct");
  for (const char* value : {"1", "0", "on"}) {
    SCOPED_TRACE(std::string("revoxelize ") + value);
    gi.setParam("revoxelize", value);
    const bool on = std::string(value) != "0";
    EXPECT_EQ(gi.params().on("revoxelize"), on);
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
