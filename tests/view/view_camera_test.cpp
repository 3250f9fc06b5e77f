// The viewer's camera moves (host/view/CameraController.hpp) on fresh random
// cameras: orbit keeps the centre and the distance to it, fly keeps the view
// vector and moves by the asked steps along view, right and up, look keeps
// the eye, pitch never reaches the up axis, and every move bumps version().
#include <gtest/gtest.h>

#include <cstdio>
#include <random>

#include "host/view/CameraController.hpp"

namespace ml {
namespace {

constexpr float kTol = 1e-3f;

float upCosine(const Camera& c) { return glm::dot(glm::normalize(c.center - c.eye), glm::normalize(c.up)); }

Camera randomCamera(std::mt19937& rng) {
  std::uniform_real_distribution<float> u(-50.0f, 50.0f);
  Camera c;
  c.center = {u(rng), u(rng), u(rng)};
  do c.eye = c.center + glm::vec3(u(rng), u(rng) * 0.5f, u(rng));
  while (glm::length(c.eye - c.center) < 1.0f || std::fabs(upCosine(c)) > 0.9f);
  return c;
}

TEST(ViewCamera, MovesKeepWhatTheyPromise) {
  const unsigned seed = std::random_device{}();
  std::printf("seed %u\n", seed);
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> angle(-200.0f, 200.0f), step(-5.0f, 5.0f);
  for (int i = 0; i < 200; ++i) {
    CameraController cc;
    const Camera c0 = randomCamera(rng);
    cc.set(c0);
    const float dist = glm::length(c0.eye - c0.center);
    std::uint64_t v = cc.version();
    cc.orbit(angle(rng), angle(rng));
    EXPECT_GT(cc.version(), v);
    EXPECT_NEAR(glm::length(cc.camera().eye - cc.camera().center), dist, kTol * dist);
    EXPECT_EQ(cc.camera().center, c0.center);
    EXPECT_LT(std::fabs(upCosine(cc.camera())), 0.9951f);

    const Camera c1 = cc.camera();
    const float f = step(rng), r = step(rng), u = step(rng);
    v = cc.version();
    cc.fly(f, r, u);
    EXPECT_GT(cc.version(), v);
    // Forward is the view direction, right is perpendicular to it and to up, up is the camera's up.
    const glm::vec3 fwd = glm::normalize(c1.center - c1.eye), up = glm::normalize(c1.up);
    const glm::vec3 right = glm::normalize(glm::cross(fwd, up));
    EXPECT_NEAR(glm::dot(cc.camera().eye - c1.eye, right), r, kTol * 10);
    EXPECT_LT(glm::length(cc.camera().eye - c1.eye - (f * fwd + r * right + u * up)), kTol * 10);
    EXPECT_LT(glm::length((cc.camera().center - cc.camera().eye) - (c1.center - c1.eye)), kTol * dist);

    const Camera c2 = cc.camera();
    cc.look(angle(rng), angle(rng));
    EXPECT_EQ(cc.camera().eye, c2.eye);
    EXPECT_NEAR(glm::length(cc.camera().center - cc.camera().eye), dist, kTol * dist);
    EXPECT_LT(std::fabs(upCosine(cc.camera())), 0.9951f);
  }
}

TEST(ViewCamera, ScrollZoomsTowardsTheCentre) {
  CameraController cc;
  Camera c;
  c.eye = {0, 0, 10};
  cc.set(c);
  cc.onScroll(1.0);
  EXPECT_NEAR(glm::length(cc.camera().eye - cc.camera().center), 9.0f, 1e-4f);
  cc.onScroll(-1.0);
  EXPECT_NEAR(glm::length(cc.camera().eye - cc.camera().center), 10.0f, 1e-4f);
}

}  // namespace
}  // namespace ml
