#include "support/BruteReference.hpp"

#include <map>

#include <gtest/gtest.h>

#include "host/assign/BruteForceAssigner.hpp"
#include "host/assign/LightFootprint.hpp"
#include "support/ImageCompare.hpp"
#include "support/TestDevice.hpp"
#include "support/TestGl.hpp"

namespace ml::test {

const SceneInputs& referenceScene() {
  static SceneInputs s = [] {
    SceneInputArgs a;
    a.lights = "1024";
    return loadSceneInputs(a);
  }();
  return s;
}

const BruteReference& bruteReference(Pipeline pipeline) {
  static std::map<Pipeline, BruteReference> cache;
  if (auto it = cache.find(pipeline); it != cache.end()) return it->second;
  glContext();
  FrameRenderer r(runtime(), referenceScene().scene, kReferenceWidth, kReferenceHeight);
  r.setLights(referenceScene().lights);
  BruteForceAssigner brute;
  BruteReference ref;
  ref.result = r.render(referenceScene().cameras.frames.front(), brute, {pipeline, true});
  ref.image = r.targets().readColor();
  return cache.emplace(pipeline, std::move(ref)).first->second;
}

FrameResult expectBruteForceFrame(FrameRenderer& r, LightAssigner& assigner, Pipeline pipeline) {
  const BruteReference& ref = bruteReference(pipeline);
  const FrameResult res = r.render(referenceScene().cameras.frames.front(), assigner, {pipeline, true});
  const auto diff = compareImages(r.targets().readColor(), ref.image, 1.0 / 255.0);
  EXPECT_LT(diff.mean_abs, 1e-4);
  EXPECT_EQ(diff.frac_over_tol, 0.0) << "max diff " << diff.max_abs;
  EXPECT_EQ(res.lower_bound, ref.result.lower_bound);
  EXPECT_EQ(res.covered_pixels, ref.result.covered_pixels);
  EXPECT_GE(res.light_evaluations, res.lower_bound);
  EXPECT_LT(res.light_evaluations, ref.result.light_evaluations / 4);
  return res;
}

FrameResult expectBruteForceFrameWith(FrameRenderer& r, LightAssigner& assigner, Pipeline pipeline,
                                      const std::vector<gpu::PointLight>& lights) {
  BruteForceAssigner brute;
  const Camera& cam = referenceScene().cameras.frames.front();
  r.setLights(lights);
  const FrameResult want = r.render(cam, brute, {pipeline, true});
  const std::vector<float> want_image = r.targets().readColor();
  const FrameResult got = r.render(cam, assigner, {pipeline, true});
  const auto diff = compareImages(r.targets().readColor(), want_image, 1.0 / 255.0);
  EXPECT_LT(diff.mean_abs, 1e-4);
  EXPECT_EQ(diff.frac_over_tol, 0.0) << "max diff " << diff.max_abs;
  EXPECT_EQ(got.lower_bound, want.lower_bound);
  EXPECT_EQ(got.covered_pixels, want.covered_pixels);
  EXPECT_GE(got.light_evaluations, got.lower_bound);
  return got;
}

std::vector<unsigned> overThreeLightSizes(FrameRenderer& r, LightAssigner& assigner, Pipeline pipeline,
                                          const std::function<unsigned(double light_pixels)>& after_frame) {
  const gpu::CameraParams cam = referenceScene().cameras.frames.front().params(kReferenceWidth, kReferenceHeight);
  const double px = coveringLightPixels(referenceScene().lights, cam);
  EXPECT_GT(px, 0.0);
  std::vector<unsigned> out;
  for (const double target : {20.0, 1000.0, 20.0}) {
    SCOPED_TRACE("radii scaled for " + std::to_string(target) + " px");
    std::vector<gpu::PointLight> lights = referenceScene().lights;
    for (auto& l : lights) l.position_radius.w *= float(target / px);
    EXPECT_GT(expectBruteForceFrameWith(r, assigner, pipeline, lights).lower_bound, 0u);
    out.push_back(after_frame(coveringLightPixels(lights, cam)));
  }
  return out;
}

double statOf(const LightAssigner& assigner, const std::string& key) {
  for (const auto& [k, v] : assigner.stats())
    if (k == key) return v;
  ADD_FAILURE() << "no statistic '" << key << "'";
  return -1.0;
}

void expectNoLightsAtOddSize(LightAssigner& assigner) {
  glContext();
  FrameRenderer r(runtime(), referenceScene().scene, 101, 37);
  r.setLights({});
  const FrameResult res = r.render(referenceScene().cameras.frames.front(), assigner, {Pipeline::Forward, true});
  EXPECT_EQ(res.light_evaluations, 0u);
  EXPECT_GT(res.covered_pixels, 0u);
}

}  // namespace ml::test
