// The GI seam is technique-blind: with voxel cone tracing in the frame
// (FrameOptions::gi, one VctGiPass for all), every built-in technique gives
// the same image as brute force of its pipeline with the same pass, within the
// render tests' tolerance (tests/hashed/hashed_render_test.cpp: mean |diff| < 0.002,
// at most 0.5% of pixels off by more than 2/255), and the indirect light
// visibly adds to the frame.
#include <gtest/gtest.h>

#include "gl/FrameRenderer.hpp"
#include "host/run/SceneInputs.hpp"
#include "host/techniques/Registry.hpp"
#include "host/vct/VctGiPass.hpp"
#include "support/ImageCompare.hpp"
#include "support/TestDevice.hpp"
#include "support/TestGl.hpp"

namespace ml::vct {
namespace {

constexpr unsigned kW = 160, kH = 90;

std::vector<float> frame(FrameRenderer& r, const std::string& technique, const Camera& cam, const Scene& scene,
                         GiPass* gi) {
  auto a = makeAssigner(technique, test::runtime(), &scene);
  r.render(cam, *a, {findTechnique(technique).pipeline, false, true, gi});
  return r.targets().readColor();
}

TEST(VctTechniques, EveryTechniqueWithVctMatchesBruteForceWithVct) {
  test::glContext();
  SceneInputArgs args;
  args.lights = "1024";
  const SceneInputs in = loadSceneInputs(args);
  const Camera& cam = in.cameras.frames.front();
  FrameRenderer r(test::runtime(), in.scene, kW, kH);
  r.setLights(in.lights);
  VctGiSettings s;
  s.grid = {32, 4, false};
  VctGiPass gi(test::runtime(), s, in.scene.bounds);
  const std::vector<float> brute[2] = {frame(r, "forward", cam, in.scene, &gi), frame(r, "deferred", cam, in.scene, &gi)};
  // The indirect light is there: the frame without it is darker.
  const std::vector<float> direct = frame(r, "deferred", cam, in.scene, nullptr);
  EXPECT_GT(test::compareImages(brute[1], direct, 2.0 / 255.0).frac_over_tol, 0.1);
  std::size_t checked = 0;
  for (const TechniqueInfo& t : techniques()) {
    if (!t.built_in || t.name == "forward" || t.name == "deferred") continue;
    SCOPED_TRACE(t.name);
    const auto img = frame(r, t.name, cam, in.scene, &gi);
    const auto diff = test::compareImages(img, brute[t.pipeline == Pipeline::Deferred], 2.0 / 255.0);
    EXPECT_LT(diff.mean_abs, 0.002) << "max " << diff.max_abs;
    EXPECT_LT(diff.frac_over_tol, 0.005) << "max " << diff.max_abs;
    ++checked;
  }
  EXPECT_GE(checked, 6u);
}

}  // namespace
}  // namespace ml::vct
