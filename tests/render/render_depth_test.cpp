// The depth buffer (issue 18, items 5 and 9): reversed-Z float depth renders a
// camera with near 1e-8 (a [-1, 1] depth mapping rounded every depth to 1 and
// rendered black), near/far beyond what float depth resolves are refused
// naming the camera file, and forward+ (depth pre-pass, then shading with an
// EQUAL test) shades the same fragment as a single depth-tested pass at the
// sizes and light counts where it once picked another face.
#include <gtest/gtest.h>

#include <map>
#include <string>

#include "gl/FrameRenderer.hpp"
#include "host/run/SceneInputs.hpp"
#include "host/techniques/Registry.hpp"
#include "host/hashed/HashedAssigner.hpp"
#include "host/util/Error.hpp"
#include "support/BruteReference.hpp"
#include "support/ImageCompare.hpp"
#include "support/TempDir.hpp"
#include "support/TestDevice.hpp"
#include "support/TestGl.hpp"

namespace ml {
namespace {

struct Frame {
  std::vector<float> image;
  FrameResult result;
};

Frame renderWith(FrameRenderer& r, const std::string& technique, const Scene& scene, const Camera& cam, bool count) {
  const TechniqueInfo& t = findTechnique(technique);
  auto assigner = makeAssigner(t.name, test::runtime(), &scene);
  Frame f;
  f.result = r.render(cam, *assigner, {t.pipeline, count});
  f.image = r.targets().readColor();
  return f;
}

// The render tests' tolerance: lights left out contribute exactly zero, so a
// technique differs from brute force only in summation order.
void expectSameImage(const std::vector<float>& got, const std::vector<float>& ref, const std::string& what) {
  const auto diff = test::compareImages(got, ref, 1.0 / 255.0);
  EXPECT_LT(diff.mean_abs, 1e-4) << what;
  EXPECT_EQ(diff.frac_over_tol, 0.0) << what << ": " << diff.frac_over_tol * double(got.size() / 4)
                                     << " pixels off, max diff " << diff.max_abs;
}

struct SizeCase {
  unsigned width, height;
  const char* lights;
};
class RenderDepthForwardPlus : public ::testing::TestWithParam<SizeCase> {};

// Item 9: with --lights 1000 at 320x240 (and 3000 at 333x177) tiled-forward
// and clustered-forward shaded another of two faces whose depths tie at a
// few pixels: EQUAL passes both and the later one was shaded, where a single
// pass (and the G-buffer) keeps the first.
TEST_P(RenderDepthForwardPlus, EveryTechniqueMatchesBruteForce) {
  test::glContext();
  const auto [w, h, lights] = GetParam();
  SceneInputArgs args;
  args.lights = lights;
  const SceneInputs in = loadSceneInputs(args);
  const Camera& cam = in.cameras.frames.front();
  FrameRenderer r(test::runtime(), in.scene, w, h);
  r.setLights(in.lights);
  const Frame brute_forward = renderWith(r, "forward", in.scene, cam, false);
  const Frame brute_deferred = renderWith(r, "deferred", in.scene, cam, false);
  for (const TechniqueInfo& t : techniques()) {
    if (t.name == "forward" || t.name == "deferred") continue;
    const Frame f = renderWith(r, t.name, in.scene, cam, false);
    expectSameImage(f.image, t.pipeline == Pipeline::Forward ? brute_forward.image : brute_deferred.image, t.name);
  }
}

INSTANTIATE_TEST_SUITE_P(Sizes, RenderDepthForwardPlus,
                         ::testing::Values(SizeCase{320, 240, "1000"}, SizeCase{333, 177, "3000"}),
                         [](const auto& info) {
                           return std::to_string(info.param.width) + "x" + std::to_string(info.param.height) + "_" +
                                  info.param.lights;
                         });

// Item 5: the default view with near 1e-8 (and with near/far at the edge of
// the accepted range) renders the image of the default near plane with every
// technique. The scene's nearest surface lies far beyond the default near, so
// nothing new comes into view; only the depth values change. 64 lights keep
// brute force cheap; the depth paths are the same at any light count.
TEST(RenderDepth, TinyNearPlaneRendersTheDefaultNearImage) {
  test::glContext();
  SceneInputArgs args;
  args.lights = "64";
  const SceneInputs in = loadSceneInputs(args);
  FrameRenderer r(test::runtime(), in.scene, 160, 90);
  r.setLights(in.lights);
  const Camera base = in.cameras.frames.front();
  std::map<std::string, Frame> at_base;
  for (const TechniqueInfo& t : techniques()) at_base[t.name] = renderWith(r, t.name, in.scene, base, true);
  ASSERT_GT(at_base["forward"].result.covered_pixels, 160u * 90u / 2);
  const std::pair<float, float> ranges[] = {{1e-8f, base.far_plane}, {2e-27f, 1e3f}};
  for (const auto& [near_plane, far_plane] : ranges) {
    Camera cam = base;
    cam.near_plane = near_plane;
    cam.far_plane = far_plane;
    ASSERT_NO_THROW(checkDepthRange(cam, "camera"));
    std::map<Pipeline, Frame> brute;
    for (const TechniqueInfo& t : techniques()) {
      const std::string what = t.name + " near " + std::to_string(near_plane) + " far " + std::to_string(far_plane);
      const Frame f = renderWith(r, t.name, in.scene, cam, true);
      if (t.name == "forward" || t.name == "deferred") brute[t.pipeline] = f;
      const Frame& want = at_base[t.pipeline == Pipeline::Forward ? "forward" : "deferred"];
      EXPECT_EQ(f.result.covered_pixels, want.result.covered_pixels) << what;
      expectSameImage(f.image, want.image, what);
      // Lists stay conservative (brute force is registered first) and as
      // tight as at the default near plane.
      ASSERT_TRUE(brute.count(t.pipeline)) << what;
      EXPECT_EQ(f.result.lower_bound, brute[t.pipeline].result.lower_bound) << what;
      EXPECT_LE(double(f.result.light_evaluations), 1.5 * double(at_base[t.name].result.light_evaluations)) << what;
    }
  }
}

TEST(CameraDepthRange, RefusesWhatFloatDepthCannotResolveNamingTheFile) {
  test::TempDir dir;
  auto camera = [&](const std::string& name, const std::string& lens) {
    return dir.write(name, R"({"eye": [0, 1, 5], "center": [0, 1, 0], )" + lens + "}");
  };
  EXPECT_NO_THROW(loadCameraJson(camera("tiny.json", R"("near": 1e-8, "far": 1000)")));
  EXPECT_NO_THROW(loadCameraJson(camera("edge.json", R"("near": 1e-30, "far": 1e-1)")));
  const std::pair<std::string, std::string> bad[] = {
      {R"("near": 1e-31, "far": 1e-2)", "1e-30"},  // near below the smallest
      {R"("near": 1e-8, "far": 1e23)", "1e+30"},   // far / near above the largest
      {R"("near": 1e-36, "far": 1)", "1e-30"},     // both: near is checked first
      {R"("near": 1e-20, "far": 1e20)", "= 1e+40"},  // the ratio as it is, not float's inf
  };
  int i = 0;
  for (const auto& [lens, limit] : bad) {
    const std::string path = camera("bad" + std::to_string(i++) + ".json", lens);
    try {
      loadCameraJson(path);
      ADD_FAILURE() << lens << " was accepted";
    } catch (const UserError& e) {
      const std::string msg = e.what();
      EXPECT_NE(msg.find(path), std::string::npos) << msg;
      EXPECT_NE(msg.find(limit), std::string::npos) << msg;
      EXPECT_EQ(msg.find('\n'), std::string::npos) << msg;
    }
  }
}

TEST(CameraDepthRange, RendererRefusesCamerasMadeInCode) {
  test::glContext();
  const SceneInputs& in = test::referenceScene();
  FrameRenderer r(test::runtime(), in.scene, 64, 36);
  Camera cam = in.cameras.frames.front();
  cam.near_plane = 1e-35f;
  auto brute = makeAssigner("forward", test::runtime());
  EXPECT_THROW(r.render(cam, *brute, {Pipeline::Forward, false}), UserError);
}

}  // namespace
}  // namespace ml
