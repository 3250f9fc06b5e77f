// VctGiPass reuses its voxel volume while nothing it reads changed, on the
// default scene through FrameRenderer (as `render` and the viewer run it):
//  - static lights over N frames (the camera at random frames of the scene's
//    path, fresh seed): one inject/mips/textures update and N traces, and
//    every frame (shaded and indirect image) bit-identical to a pass that
//    updates on every frame (its renderer is given the same lights again
//    before each frame);
//  - lights moved before frame k: frame k updates, and it and the frames after
//    it equal a fresh pass's on the moved lights (bit for bit with brute-force
//    injection; within the incremental hashed lists' rounding otherwise),
//    which differ visibly from the stale volume's image;
//  - lights moved before a frame rendered without the pass (a counted frame,
//    as the viewer's heat maps): the next frame with the pass still updates;
//  - --revoxelize: every frame updates (and voxelizes); so does a caller that
//    gives no lights version (0);
//  - the viewer (ViewerGi): a settings change that alters the volume gives the
//    next frame a new, updated volume, equal to a fresh pass's.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <random>
#include <string>
#include <vector>

#include "gl/FrameRenderer.hpp"
#include "host/run/SceneInputs.hpp"
#include "host/run/RunLayer.hpp"
#include "host/scene/LightAnimator.hpp"
#include "host/techniques/Registry.hpp"
#include "host/vct/VctGiDescriptor.hpp"
#include "host/vct/VctGiPass.hpp"
#include "host/view/ViewerGi.hpp"
#include "support/ImageCompare.hpp"
#include "support/TestDevice.hpp"
#include "support/TestGl.hpp"

namespace ml::vct {
namespace {

constexpr unsigned kW = 64, kH = 40;
constexpr const char* kVolumePasses[] = {"vct-lists", "vct-inject", "vct-mips", "vct-textures"};

const SceneInputs& sceneInputs() {
  static const SceneInputs in = [] {
    SceneInputArgs args;
    args.lights = "256";
    return loadSceneInputs(args);
  }();
  return in;
}

VctGiSettings smallSettings() {
  VctGiSettings s;
  s.grid = {16, 3, false};
  return s;
}

struct Frame {
  std::vector<float> color, indirect;
  PassTimings passes;
};

// A renderer, a brute-force deferred assigner and a GI pass of its own.
struct Rig {
  FrameRenderer renderer;
  std::unique_ptr<LightAssigner> assigner;
  GiPass* gi;

  Rig(const std::vector<gpu::PointLight>& lights, GiPass* pass)
      : renderer(test::runtime(), sceneInputs().scene, kW, kH),
        assigner(makeAssigner("deferred", test::runtime(), &sceneInputs().scene)),
        gi(pass) {
    renderer.setLights(lights);
  }
  Frame render(const Camera& camera) {
    const FrameResult r = renderer.render(camera, *assigner, {Pipeline::Deferred, false, true, gi});
    return {renderer.targets().readColor(), gi->indirectRgba(), r.passes};
  }
};

bool ran(const PassTimings& t, const char* pass) {
  for (const auto& e : t.entries())
    if (e.first == pass) return true;
  return false;
}
bool ran(const Frame& f, const char* pass) { return ran(f.passes, pass); }

// "" when equal bit for bit, else the first difference.
std::string firstDifference(const std::vector<float>& a, const std::vector<float>& b) {
  if (a.size() != b.size()) return "sizes differ";
  for (std::size_t i = 0; i < a.size(); ++i)
    if (std::memcmp(&a[i], &b[i], sizeof(float)) != 0)
      return "value " + std::to_string(i) + ": " + std::to_string(a[i]) + " vs " + std::to_string(b[i]);
  return "";
}

// `n` distinct frames of the scene's camera path, in random order (inside the
// scene: a camera moved at random may see a flat wall whose frames are equal).
std::vector<Camera> pathCameras(std::mt19937_64& rng, std::size_t n) {
  const std::vector<Camera>& path = sceneInputs().cameras.frames;
  std::vector<std::size_t> index(path.size());
  for (std::size_t i = 0; i < index.size(); ++i) index[i] = i;
  std::shuffle(index.begin(), index.end(), rng);
  std::vector<Camera> cams;
  for (std::size_t i = 0; i < n && i < index.size(); ++i) cams.push_back(path[index[i]]);
  return cams;
}

TEST(VctReuse, StaticLightsUpdateOnceAndEqualAPassThatUpdatesEveryFrame) {
  test::glContext();
  const std::uint64_t seed = test::freshSeed();
  SCOPED_TRACE("seed=" + std::to_string(seed));
  std::mt19937_64 rng(seed);
  constexpr std::size_t kFrames = 5;
  const std::vector<Camera> cams = pathCameras(rng, kFrames);
  ASSERT_EQ(cams.size(), kFrames) << "the camera path is too short";
  const auto& lights = sceneInputs().lights;
  VctGiPass reusing(test::runtime(), smallSettings(), sceneInputs().scene.bounds);
  VctGiPass updating(test::runtime(), smallSettings(), sceneInputs().scene.bounds);
  Rig a(lights, &reusing), b(lights, &updating);
  std::vector<float> previous;
  for (std::size_t f = 0; f < kFrames; ++f) {
    SCOPED_TRACE("frame " + std::to_string(f));
    b.renderer.setLights(lights);  // the same lights, a new version: an update every frame
    const Frame got = a.render(cams[f]), want = b.render(cams[f]);
    for (const char* pass : kVolumePasses) {
      EXPECT_EQ(ran(got, pass), f == 0) << pass;
      EXPECT_TRUE(ran(want, pass)) << pass;
    }
    EXPECT_TRUE(ran(got, "vct-trace"));
    EXPECT_TRUE(ran(got, "vct-upsample"));
    EXPECT_EQ(firstDifference(got.indirect, want.indirect), "") << "indirect image";
    EXPECT_EQ(firstDifference(got.color, want.color), "") << "shaded image";
    // The camera moved: a trace that did not run again would show the last frame.
    if (f > 0) {
      EXPECT_NE(firstDifference(got.indirect, previous), "") << "the indirect image did not follow the camera";
    }
    previous = got.indirect;
  }
  EXPECT_EQ(reusing.volumeUpdates(), 1u);
  EXPECT_EQ(reusing.volumeReuses(), kFrames - 1);
  EXPECT_EQ(updating.volumeUpdates(), kFrames);
  EXPECT_EQ(updating.volumeReuses(), 0u);
}

// Frames 0..kFrames-1 with the lights moved before frame k; every frame from
// k on is compared with a fresh pass on the moved lights.
void checkLightsMovedOnFrameK(bool brute_inject) {
  const std::uint64_t seed = test::freshSeed();
  SCOPED_TRACE("seed=" + std::to_string(seed));
  std::mt19937_64 rng(seed);
  constexpr std::size_t kFrames = 4;
  const std::size_t k = 1 + rng() % (kFrames - 1);
  SCOPED_TRACE("lights move before frame " + std::to_string(k));
  const Camera& cam = sceneInputs().cameras.frames.front();
  VctGiSettings s = smallSettings();
  s.brute_inject = brute_inject;
  LightAnimator animator(sceneInputs().lights, 0.5, seed, 1.0);
  const std::vector<gpu::PointLight> moved = animator.step();
  VctGiPass pass(test::runtime(), s, sceneInputs().scene.bounds);
  Rig rig(sceneInputs().lights, &pass);
  VctGiPass fresh_pass(test::runtime(), s, sceneInputs().scene.bounds);
  Rig fresh(moved, &fresh_pass);
  const Frame want = fresh.render(cam);
  std::vector<float> stale;
  for (std::size_t f = 0; f < kFrames; ++f) {
    SCOPED_TRACE("frame " + std::to_string(f));
    if (f == k) rig.renderer.setLights(moved);
    const Frame got = rig.render(cam);
    EXPECT_EQ(ran(got, "vct-inject"), f == 0 || f == k);
    if (f < k) {
      stale = got.indirect;
      continue;
    }
    if (brute_inject) {
      EXPECT_EQ(firstDifference(got.indirect, want.indirect), "") << "indirect image";
      EXPECT_EQ(firstDifference(got.color, want.color), "") << "shaded image";
    } else {
      const test::ImageDiff d = test::compareImages(got.indirect, want.indirect, 1e-4);
      EXPECT_LT(d.max_abs, 1e-4) << "indirect image";
    }
  }
  // The moved lights light the scene visibly otherwise: a stale volume fails above.
  EXPECT_GT(test::compareImages(stale, want.indirect, 1e-3).frac_over_tol, 0.05);
  EXPECT_EQ(pass.volumeUpdates(), 2u);
  EXPECT_EQ(pass.volumeReuses(), kFrames - 2);
}

TEST(VctReuse, LightsMovedOnFrameKUpdateThatFrameBruteInjection) {
  test::glContext();
  checkLightsMovedOnFrameK(true);
}

TEST(VctReuse, LightsMovedOnFrameKUpdateThatFrameHashedLists) {
  test::glContext();
  checkLightsMovedOnFrameK(false);
}

// A counted frame runs no GI pass but takes the renderer's lights_changed;
// the lights' version still tells the pass its volume is stale.
TEST(VctReuse, LightsMovedBeforeAFrameWithoutThePassStillUpdate) {
  test::glContext();
  const std::uint64_t seed = test::freshSeed();
  SCOPED_TRACE("seed=" + std::to_string(seed));
  const Camera& cam = sceneInputs().cameras.frames.front();
  VctGiSettings s = smallSettings();
  s.brute_inject = true;
  LightAnimator animator(sceneInputs().lights, 0.5, seed, 1.0);
  const std::vector<gpu::PointLight> moved = animator.step();
  VctGiPass pass(test::runtime(), s, sceneInputs().scene.bounds);
  Rig rig(sceneInputs().lights, &pass);
  rig.render(cam);
  rig.renderer.setLights(moved);
  countedRender(rig.renderer, *rig.assigner, {Pipeline::Deferred, false, true, &pass}, cam);
  const Frame got = rig.render(cam);
  EXPECT_TRUE(ran(got, "vct-inject"));
  EXPECT_EQ(pass.volumeUpdates(), 2u);
  VctGiPass fresh_pass(test::runtime(), s, sceneInputs().scene.bounds);
  Rig fresh(moved, &fresh_pass);
  EXPECT_EQ(firstDifference(got.indirect, fresh.render(cam).indirect), "");
}

// A caller that does not identify its lights (lights_version 0, the
// default) gets an update on every frame, the first one included.
TEST(VctReuse, UnknownLightsVersionUpdatesEveryFrame) {
  test::glContext();
  VctGiPass pass(test::runtime(), smallSettings(), sceneInputs().scene.bounds);
  SceneGpu scene(sceneInputs().scene);
  for (int f = 0; f < 3; ++f) {
    PassTimings t;
    pass.update({scene, sceneInputs().lights, t});
    EXPECT_TRUE(ran(t, "vct-inject")) << "frame " << f;
  }
  EXPECT_EQ(pass.volumeUpdates(), 3u);
  EXPECT_EQ(pass.volumeReuses(), 0u);
}

TEST(VctReuse, RevoxelizeUpdatesEveryFrame) {
  test::glContext();
  VctGiSettings s = smallSettings();
  s.revoxelize = true;
  VctGiPass pass(test::runtime(), s, sceneInputs().scene.bounds);
  Rig rig(sceneInputs().lights, &pass);
  constexpr std::size_t kFrames = 3;
  for (std::size_t f = 0; f < kFrames; ++f) {
    const Frame got = rig.render(sceneInputs().cameras.frames.front());
    for (const char* p : {"vct-voxelize", "vct-inject", "vct-mips", "vct-textures"})
      EXPECT_TRUE(ran(got, p)) << p << " frame " << f;
  }
  EXPECT_EQ(pass.volumeUpdates(), kFrames);
  EXPECT_EQ(pass.pipeline().voxelizations(), kFrames);
  EXPECT_EQ(pass.volumeReuses(), 0u);
}

// The viewer's gi_param: a change that alters the volume (here the voxel
// count, then voxel shadows) reaches the next frame as a new volume, updated
// from the unchanged lights, equal to a fresh pass's with those settings.
TEST(VctReuse, ViewerSettingChangeUpdatesTheNextFrame) {
  test::glContext();
  const Camera& cam = sceneInputs().cameras.frames.front();
  ViewerGi gi(test::runtime(), sceneInputs().scene);
  gi.setParam("voxels", "16");
  gi.setParam("levels", "3");
  gi.setMode("vct");
  Rig rig(sceneInputs().lights, gi.pass());
  std::vector<float> before;
  for (int f = 0; f < 2; ++f) before = rig.render(cam).indirect;
  for (const auto& [key, value] : {std::pair<std::string, std::string>{"voxels", "32"}, {"vct-shadows", "voxel"}}) {
    SCOPED_TRACE(key + "=" + value);
    gi.setParam(key, value);
    rig.gi = gi.pass();
    const Frame got = rig.render(cam);
    auto* pass = dynamic_cast<VctGiPass*>(gi.pass());
    ASSERT_NE(pass, nullptr);
    EXPECT_TRUE(ran(got, "vct-inject"));
    EXPECT_EQ(pass->volumeUpdates(), 1u);
    VctGiPass fresh_pass(test::runtime(), vctSettingsOf(gi.params()), sceneInputs().scene.bounds);
    Rig fresh(sceneInputs().lights, &fresh_pass);
    EXPECT_EQ(firstDifference(got.indirect, fresh.render(cam).indirect), "");
    EXPECT_GT(test::compareImages(got.indirect, before, 1e-3).frac_over_tol, 0.01) << "the setting changed nothing";
    before = got.indirect;
    rig.render(cam);
    EXPECT_EQ(pass->volumeReuses(), 1u) << "the new volume is reused while nothing changes";
  }
}

}  // namespace
}  // namespace ml::vct
