// Brute-force forward and deferred on the default scene: the two pipelines
// agree, lights visibly contribute, and the counters are right.
#include <gtest/gtest.h>

#include <glm/gtc/matrix_transform.hpp>

#include "gl/FrameRenderer.hpp"
#include "host/run/SceneInputs.hpp"
#include "host/assign/BruteForceAssigner.hpp"
#include "support/DepthPoints.hpp"
#include "support/ImageCompare.hpp"
#include "support/TestDevice.hpp"
#include "support/TestGl.hpp"

namespace ml {
namespace {

constexpr unsigned kW = 320, kH = 180;

struct DefaultScene {
  SceneInputs inputs;
  DefaultScene() {
    SceneInputArgs a;
    a.lights = "1024";
    inputs = loadSceneInputs(a);
  }
};

const DefaultScene& defaultScene() {
  static DefaultScene s;
  return s;
}

// Independent CPU count of lights whose sphere contains each covered pixel's
// surface point, reconstructed from the depth buffer.
std::uint64_t cpuLowerBound(const std::vector<float>& depth, const Camera& cam,
                            const std::vector<gpu::PointLight>& lights, std::uint64_t& covered) {
  const gpu::CameraParams params = cam.params(kW, kH);
  std::uint64_t total = 0;
  covered = 0;
  for (unsigned y = 0; y < kH; ++y)
    for (unsigned x = 0; x < kW; ++x) {
      const float d = depth[y * kW + x];
      if (gpu::is_sky_depth(d)) continue;
      ++covered;
      const glm::vec3 p = test::pixelWorldPoint(cam, params, x, y, d);
      for (const auto& l : lights) {
        glm::vec3 dv = glm::vec3(l.position_radius.x, l.position_radius.y, l.position_radius.z) - p;
        if (glm::dot(dv, dv) < l.position_radius.w * l.position_radius.w) ++total;
      }
    }
  return total;
}

TEST(RenderBrute, ForwardAndDeferredAgreeAndCountsAreExact) {
  test::glContext();
  const auto& in = defaultScene().inputs;
  FrameRenderer r(test::runtime(), in.scene, kW, kH);
  r.setLights(in.lights);
  BruteForceAssigner brute;
  const Camera& cam = in.cameras.frames.front();

  FrameOptions fwd{Pipeline::Forward, true};
  FrameResult rf = r.render(cam, brute, fwd);
  const auto img_forward = r.targets().readColor();
  const auto depth_forward = r.targets().readDepth(false);

  FrameOptions def{Pipeline::Deferred, true};
  FrameResult rd = r.render(cam, brute, def);
  const auto img_deferred = r.targets().readColor();

  // Same picture. Deferred reconstructs position from 32-bit depth and stores
  // normals octahedral in RG16 unorm; the stated tolerance: mean |diff| < 0.002 and no
  // more than 0.5% of pixels off by more than 2/255 in any channel.
  const auto diff = test::compareImages(img_forward, img_deferred, 2.0 / 255.0);
  EXPECT_LT(diff.mean_abs, 0.002) << "max " << diff.max_abs;
  EXPECT_LT(diff.frac_over_tol, 0.005) << "max " << diff.max_abs;

  // Lights visibly contribute: not uniform, and brighter than ambient alone.
  EXPECT_GT(test::luminanceStdDev(img_forward), 0.02);

  // Brute force evaluates every light at every covered pixel.
  ASSERT_GT(rf.covered_pixels, kW * kH / 4);
  EXPECT_EQ(rf.covered_pixels, rd.covered_pixels);
  EXPECT_EQ(rf.light_evaluations, std::uint64_t(in.lights.size()) * rf.covered_pixels);
  EXPECT_EQ(rd.light_evaluations, std::uint64_t(in.lights.size()) * rd.covered_pixels);
  // Forward without a pre-pass shades hidden fragments too.
  EXPECT_GE(rf.fragment_evaluations, rf.light_evaluations);
  EXPECT_EQ(rd.fragment_evaluations, rd.light_evaluations);

  // The lower bound matches an independent CPU count (boundary cases may flip
  // with float rounding: allow 0.1%).
  std::uint64_t covered = 0;
  const std::uint64_t cpu = cpuLowerBound(depth_forward, cam, in.lights, covered);
  EXPECT_EQ(covered, rf.covered_pixels);
  ASSERT_GT(cpu, 0u);
  EXPECT_NEAR(double(rf.lower_bound), double(cpu), 0.001 * double(cpu));
  EXPECT_NEAR(double(rd.lower_bound), double(cpu), 0.001 * double(cpu));
  EXPECT_LT(rf.lower_bound, rf.light_evaluations);
}

TEST(RenderBrute, NoLightsGivesAmbientOnly) {
  test::glContext();
  const auto& in = defaultScene().inputs;
  FrameRenderer r(test::runtime(), in.scene, 64, 36);
  r.setLights({});
  BruteForceAssigner brute;
  FrameResult res = r.render(in.cameras.frames.front(), brute, {Pipeline::Deferred, true});
  EXPECT_EQ(res.light_evaluations, 0u);
  EXPECT_EQ(res.lower_bound, 0u);
  const auto img = r.targets().readColor();
  float maxv = 0;
  for (size_t i = 0; i < img.size(); i += 4) maxv = std::max({maxv, img[i], img[i + 1], img[i + 2]});
  EXPECT_LE(maxv, 0.1f + 1e-5f);  // ambient 0.1 x base colour <= 1
  EXPECT_GT(maxv, 0.0f);
}

}  // namespace
}  // namespace ml
