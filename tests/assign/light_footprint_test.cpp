// coveringLightPixels() and tileForLights(): the lights' size on screen that
// the automatic cluster and tile sizes follow, against values computed by
// hand from a camera looking down -z (fresh random radii and distances).
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "host/assign/LightFootprint.hpp"
#include "host/scene/Camera.hpp"
#include "host/scene/LightSet.hpp"
#include "support/TestDevice.hpp"

namespace ml {
namespace {

gpu::CameraParams lookDownZ(unsigned w, unsigned h) {
  Camera c;
  c.eye = glm::vec3(0.0f);
  c.center = glm::vec3(0.0f, 0.0f, -1.0f);
  c.fovy_degrees = 60.0f;
  c.near_plane = 0.1f;
  c.far_plane = 100.0f;
  return c.params(w, h);
}

double pixelsOf(float r, float z, const gpu::CameraParams& cam) {
  return double(r) * cam.height / (2.0 * cam.tan_half_fovy * z);
}

TEST(LightFootprint, AreaWeightedMedianOfTheLightsInView) {
  const std::uint64_t seed = test::freshSeed();
  SCOPED_TRACE("seed " + std::to_string(seed));
  std::mt19937_64 rng(seed);
  const gpu::CameraParams cam = lookDownZ(640, 360);
  const float r = std::uniform_real_distribution<float>(0.05f, 0.5f)(rng);
  const float near_z = std::uniform_real_distribution<float>(2.0f, 5.0f)(rng), far_z = near_z * 4.0f;
  std::vector<gpu::PointLight> lights;
  // n far lights of a quarter the near ones' size: each weighs 1/16 of a near one.
  const int near_count = 1 + int(rng() % 5), far_count = 16 * near_count - 1 - int(rng() % 3);
  for (int i = 0; i < near_count; ++i) lights.push_back(makeLight({0.0f, 0.0f, -near_z}, r, glm::vec3(1)));
  for (int i = 0; i < far_count; ++i) lights.push_back(makeLight({0.0f, 0.0f, -far_z}, r, glm::vec3(1)));
  // Left out: behind the camera, reaching it, beyond far, beside the view.
  lights.push_back(makeLight({0.0f, 0.0f, 3.0f}, r, glm::vec3(1)));
  lights.push_back(makeLight({0.0f, 0.0f, -r * 0.5f}, r, glm::vec3(1)));
  lights.push_back(makeLight({0.0f, 0.0f, -500.0f}, r, glm::vec3(1)));
  lights.push_back(makeLight({50.0f, 0.0f, -near_z}, r, glm::vec3(1)));
  // The far lights weigh less than half: the median is the near lights' size.
  EXPECT_NEAR(coveringLightPixels(lights, cam), pixelsOf(r, near_z, cam), 1e-3 * pixelsOf(r, near_z, cam));
  for (int i = 0; i < 4; ++i) lights.push_back(makeLight({0.0f, 0.0f, -far_z}, r, glm::vec3(1)));
  EXPECT_NEAR(coveringLightPixels(lights, cam), pixelsOf(r, far_z, cam), 1e-3 * pixelsOf(r, far_z, cam));
  EXPECT_EQ(coveringLightPixels({}, cam), 0.0);
  EXPECT_EQ(coveringLightPixels({lights[std::size_t(near_count + far_count)]}, cam), 0.0) << "behind: none in view";
}

// Past kFootprintSamples lights a fixed stride is read: the same answer
// twice, and close to the answer over all of them.
TEST(LightFootprint, SampledAnswerIsRepeatableAndClose) {
  const std::uint64_t seed = test::freshSeed();
  SCOPED_TRACE("seed " + std::to_string(seed));
  std::mt19937_64 rng(seed);
  const gpu::CameraParams cam = lookDownZ(320, 320);
  std::uniform_real_distribution<float> xy(-1.0f, 1.0f), z(2.0f, 40.0f);
  std::vector<gpu::PointLight> lights;
  for (std::size_t i = 0; i < 3 * kFootprintSamples + 7; ++i) {
    const float d = z(rng);
    lights.push_back(makeLight({xy(rng) * 0.5f * d, xy(rng) * 0.5f * d, -d}, 0.2f, glm::vec3(1)));
  }
  const double a = coveringLightPixels(lights, cam);
  EXPECT_EQ(a, coveringLightPixels(lights, cam));
  std::vector<gpu::PointLight> first(lights.begin(), lights.begin() + std::ptrdiff_t(kFootprintSamples));
  EXPECT_NEAR(a, coveringLightPixels(first, cam), 0.1 * a);
}

TEST(LightFootprint, TileIsTheLargestPowerOfTwoWithinTheRatio) {
  EXPECT_EQ(tileForLights(0.0, 0.14, 8, 32), 32u) << "no light in view";
  EXPECT_EQ(tileForLights(1000.0, 0.14, 8, 32), 32u);
  EXPECT_EQ(tileForLights(32.0 / 0.14, 0.14, 8, 32), 32u);
  EXPECT_EQ(tileForLights(31.9 / 0.14, 0.14, 8, 32), 16u);
  EXPECT_EQ(tileForLights(63.0, 0.14, 8, 32), 8u);   // 8.8 px
  EXPECT_EQ(tileForLights(1.0, 0.14, 8, 32), 8u);    // never below lo
  EXPECT_EQ(tileForLights(150.0, 0.14, 8, 16), 16u);  // never above hi
}

}  // namespace
}  // namespace ml
