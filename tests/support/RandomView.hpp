#pragma once
// Random views for the light-assignment tests (tiled culling, clustered keys
// and assignment): a depth buffer of sloped rectangles at random distances
// over sky, so tiles and clusters see empty space, single surfaces and depth
// discontinuities; and lights around the view: in front, behind, huge ones,
// ones containing the eye or straddling the near plane.
#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <random>
#include <vector>

#include "host/scene/Camera.hpp"
#include "host/scene/LightSet.hpp"

namespace ml::test {

struct RandomView {
  Camera camera;
  unsigned width = 0, height = 0;
  std::vector<float> depth;  // window depth, row 0 bottom
  std::vector<gpu::PointLight> lights;
  gpu::CameraParams cam() const { return camera.params(width, height); }
};

// What the depth rectangles and lights look like.
struct ViewShape {
  float far_plane = 100.0f;
  float depth_near = 0.5f, depth_span = 30.0f;  // a rectangle's distance: near + U(0,1) * span
  float slope = 0.2f;                           // distance change per pixel: U(-slope/2, slope/2)
  float min_distance = 0.2f;
  bool tiny_near_lights = false;  // every 29th light: radius 0.02 at the near plane
};

inline void addDepthRectangles(RandomView& c, std::mt19937_64& rng, const ViewShape& s) {
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  const unsigned w = c.width, h = c.height;
  const glm::mat4 proj = c.camera.projection(float(w) / float(h));
  auto window_depth = [&](float dist) { return gpu::distance_to_depth(dist, proj[2][2], proj[3][2]); };
  c.depth.assign(std::size_t(w) * h, gpu::kSkyDepth);
  for (int r = 0; r < 12; ++r) {
    const unsigned x0 = unsigned(u(rng) * w), y0 = unsigned(u(rng) * h);
    const unsigned x1 = std::min(w, x0 + 1 + unsigned(u(rng) * w / 2)), y1 = std::min(h, y0 + 1 + unsigned(u(rng) * h / 2));
    const float d0 = s.depth_near + u(rng) * s.depth_span, slope = (u(rng) - 0.5f) * s.slope;
    for (unsigned y = y0; y < y1; ++y)
      for (unsigned x = x0; x < x1; ++x)
        c.depth[y * w + x] = window_depth(std::clamp(d0 + slope * float(x - x0), s.min_distance, s.far_plane));
  }
}

inline void addLightsAroundView(RandomView& c, std::mt19937_64& rng, std::size_t n_lights, const ViewShape& s) {
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  const glm::mat4 inv_view = glm::inverse(c.camera.view());
  for (std::size_t i = 0; i < n_lights; ++i) {
    glm::vec3 v{u(rng) * 40 - 20, u(rng) * 30 - 15, -u(rng) * 40 + 5};
    float r = 0.2f + u(rng) * 4;
    if (i % 17 == 0) r = 20 + u(rng) * 30;                       // huge
    if (i % 23 == 0) v = {u(rng) - 0.5f, u(rng) - 0.5f, -0.1f};  // straddling near / around the eye
    if (s.tiny_near_lights && i % 29 == 0) v.z = -0.1f + (u(rng) - 0.5f) * 0.05f, r = 0.02f;
    const glm::vec3 world = glm::vec3(inv_view * glm::vec4(v, 1));
    c.lights.push_back(makeLight(world, r, {u(rng), u(rng), u(rng)}));
  }
}

inline RandomView randomView(std::mt19937_64& rng, unsigned w, unsigned h, std::size_t n_lights,
                             const ViewShape& s = {}) {
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  RandomView c;
  c.width = w;
  c.height = h;
  c.camera.eye = {u(rng) * 4 - 2, u(rng) * 2, u(rng) * 4 - 2};
  c.camera.center = c.camera.eye + glm::vec3(u(rng) - 0.5f, u(rng) * 0.4f - 0.2f, -1.0f);
  c.camera.fovy_degrees = 30 + u(rng) * 60;
  c.camera.near_plane = 0.1f;
  c.camera.far_plane = s.far_plane;
  addDepthRectangles(c, rng, s);
  addLightsAroundView(c, rng, n_lights, s);
  return c;
}

}  // namespace ml::test
