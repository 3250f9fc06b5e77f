// No per-pixel light limit, and one exact lower bound for every technique.
// llvmpipe ends a shader invocation's loops after 65,535 iterations in total;
// with 66,000 lights reaching every pixel, the lit ones last, a light loop
// that stops there renders the unlit image. Every registered technique must
// render brute force's image, and all must report the same lower bound.
#include "ml_test_paths.h"  // MANYLIGHTS_TEST_DATA_DIR (generated)
#include <gtest/gtest.h>

#include "gl/FrameRenderer.hpp"
#include "host/techniques/Registry.hpp"
#include "host/scene/LightSet.hpp"
#include "support/BruteReference.hpp"
#include "support/ImageCompare.hpp"
#include "support/TestDevice.hpp"
#include "support/TestGl.hpp"

namespace ml {
namespace {

constexpr unsigned kW = 16, kH = 12;
constexpr std::uint32_t kLights = 66000, kLit = 8;

// The default scene's volumes with a fixed radius: list lengths grow with the count.
std::vector<gpu::PointLight> defaultSceneLights(std::uint32_t count, std::uint64_t seed) {
  const std::string volumes = std::string(MANYLIGHTS_TEST_DATA_DIR) + "/default/light_volumes.json";
  return generateLightsIn(volumes, {}, {}, count, seed, 1.5f);
}

// Every light's sphere holds the whole scene; the first kLights - kLit are dark.
std::vector<gpu::PointLight> crowdedLights(const Camera& cam) {
  std::vector<gpu::PointLight> lights;
  const glm::vec3 c = cam.eye;
  for (std::uint32_t i = 0; i < kLights; ++i) {
    const bool lit = i >= kLights - kLit;
    const float a = 0.7f * float(i % 97);
    const glm::vec3 p = c + glm::vec3(3.0f * std::cos(a), 1.0f + 0.01f * float(i % 7), 3.0f * std::sin(a));
    lights.push_back(makeLight(p, 1000.0f, lit ? glm::vec3(1.0f, 0.8f, 0.6f) : glm::vec3(0.0f)));
  }
  return lights;
}

struct Frame {
  std::vector<float> image;
  FrameResult result;
};

// With the scene: hashed shading masks its octree with the scene's geometry by default.
Frame renderWith(FrameRenderer& r, const Camera& cam, const std::string& technique) {
  const auto assigner = makeAssigner(technique, test::runtime(), &test::referenceScene().scene);
  Frame f;
  f.result = r.render(cam, *assigner, {findTechnique(technique).pipeline, true});
  f.image = r.targets().readColor();
  return f;
}

TEST(RenderLightLimit, MoreThan65535LightsPerPixelReachEveryTechnique) {
  test::glContext();
  const SceneInputs& in = test::referenceScene();
  const Camera& cam = in.cameras.frames.front();
  FrameRenderer r(test::runtime(), in.scene, kW, kH);
  r.setLights({});
  const Frame unlit_forward = renderWith(r, cam, "forward");
  r.setLights(crowdedLights(cam));
  const Frame brute[2] = {renderWith(r, cam, "forward"), renderWith(r, cam, "deferred")};
  const std::uint64_t covered = brute[0].result.covered_pixels;
  ASSERT_GT(covered, kW * kH / 2);
  for (const auto& t : techniques()) {
    SCOPED_TRACE(t.name);
    const Frame f = renderWith(r, cam, t.name);
    const Frame& ref = brute[t.pipeline == Pipeline::Forward ? 0 : 1];
    // Lit lights are last: dropping the tail of a list leaves the unlit image.
    const auto lit = test::compareImages(f.image, unlit_forward.image, 2.0 / 255.0);
    EXPECT_GT(lit.frac_over_tol, 0.5) << "the lit lights past the 65,535th were dropped";
    const auto diff = test::compareImages(f.image, ref.image, 1.0 / 255.0);
    EXPECT_LT(diff.mean_abs, 1e-4);
    EXPECT_EQ(diff.frac_over_tol, 0.0) << "max diff " << diff.max_abs;
    EXPECT_EQ(f.result.covered_pixels, covered);
    EXPECT_EQ(f.result.lower_bound, std::uint64_t(kLights) * covered);  // every light holds every point
    EXPECT_EQ(f.result.missed_lights, 0u);
    EXPECT_GE(f.result.light_evaluations, f.result.lower_bound);
  }
}

TEST(RenderLightLimit, EveryTechniqueReportsTheSameLowerBound) {
  test::glContext();
  const SceneInputs& in = test::referenceScene();
  const Camera& cam = in.cameras.frames.front();
  constexpr unsigned w = 160, h = 90;
  FrameRenderer r(test::runtime(), in.scene, w, h);
  r.setLights(in.lights);
  // The bound from every light, in C++, over this frame's depth.
  const Frame first = renderWith(r, cam, "deferred");
  const auto depth = r.targets().readDepth(true);
  const gpu::BoundParams p = boundParams(cam.view(), cam.projection(float(w) / float(h)), w, h);
  std::uint64_t cpu = 0;
  for (unsigned y = 0; y < h; ++y)
    for (unsigned x = 0; x < w; ++x) {
      glm::vec3 P;
      if (!windowToWorld(depth[std::size_t(y) * w + x], x, y, p, P)) continue;
      for (const auto& l : in.lights) {
        const auto& L = l.position_radius;
        const float dx = L.x - P.x, dy = L.y - P.y, dz = L.z - P.z;
        cpu += dx * dx + dy * dy + dz * dz < L.w * L.w;
      }
    }
  ASSERT_GT(cpu, 0u);
  EXPECT_EQ(first.result.lower_bound, cpu);
  for (const auto& t : techniques()) {
    SCOPED_TRACE(t.name);
    const Frame f = renderWith(r, cam, t.name);
    EXPECT_EQ(f.result.lower_bound, cpu);
    EXPECT_EQ(f.result.covered_pixels, first.result.covered_pixels);
    EXPECT_EQ(f.result.missed_lights, 0u);
    EXPECT_GE(f.result.light_evaluations, f.result.lower_bound);
  }
}

// Issue 17, item 3: structures sized by one frame must grow (or report) when
// the next frame's lists are longer, never drop what does not fit. One
// assigner per technique renders 300 lights, then 20x as many at the same
// radius (every tile, cluster and hash cell list about 20x longer), then the
// small set and the large one again: no bound light is missed, and every
// technique counts the same bound.
TEST(RenderLightLimit, ListsSizedByASmallSetGrowForALargeOne) {
  test::glContext();
  const std::uint64_t seed = test::freshSeed();
  SCOPED_TRACE("seed " + std::to_string(seed));
  const SceneInputs& in = test::referenceScene();
  const Camera& cam = in.cameras.frames.front();
  FrameRenderer r(test::runtime(), in.scene, 160, 90);
  const std::vector<gpu::PointLight> sets[2] = {defaultSceneLights(300, seed), defaultSceneLights(6000, seed + 1)};
  std::uint64_t bound[2] = {0, 0};
  for (const auto& t : techniques()) {
    if (t.name == "forward" || t.name == "deferred") continue;  // brute force keeps no lists
    SCOPED_TRACE(t.name);
    const auto assigner = makeAssigner(t.name, test::runtime(), &in.scene);
    for (const int s : {0, 1, 0, 1}) {
      r.setLights(sets[s]);
      const FrameResult f = r.render(cam, *assigner, {t.pipeline, true});
      EXPECT_EQ(f.missed_lights, 0u) << "set " << s;
      EXPECT_GE(f.light_evaluations, f.lower_bound) << "set " << s;
      if (bound[s] == 0) bound[s] = f.lower_bound;
      EXPECT_EQ(f.lower_bound, bound[s]) << "set " << s;
    }
  }
  EXPECT_GT(bound[1], 10 * bound[0]);  // the large set's lists really are longer
}

}  // namespace
}  // namespace ml
