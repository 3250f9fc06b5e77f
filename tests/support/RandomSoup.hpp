#pragma once
// Random triangle soups and lights for the voxel cone tracing tests: triangles
// in [-1, 1]^3 with random colours (one material each), and finite point
// lights inside an AABB with radii up to its diagonal.
#include <glm/glm.hpp>

#include <random>
#include <vector>

#include "host/scene/LightSet.hpp"
#include "host/scene/Scene.hpp"

namespace ml::test {

inline float uniformIn(std::mt19937_64& rng, float a, float b) {
  return std::uniform_real_distribution<float>(a, b)(rng);
}

inline Scene randomSoup(std::mt19937_64& rng, std::size_t triangles) {
  Scene s;
  s.source = "random triangles";
  for (std::size_t t = 0; t < triangles; ++t) {
    glm::vec3 p[3];
    for (auto& q : p) q = {uniformIn(rng, -1, 1), uniformIn(rng, -1, 1), uniformIn(rng, -1, 1)};
    glm::vec3 n = glm::cross(p[1] - p[0], p[2] - p[0]);
    n = glm::length(n) > 0 ? glm::normalize(n) : glm::vec3(0, 1, 0);
    const auto first = static_cast<std::uint32_t>(s.indices.size());
    for (const auto& q : p) {
      s.vertices.push_back({q, n, glm::vec2(0.0f)});
      s.indices.push_back(static_cast<std::uint32_t>(s.indices.size()));
      s.bounds.extend(q);
    }
    s.materials.push_back({glm::vec4(uniformIn(rng, 0, 1), uniformIn(rng, 0, 1), uniformIn(rng, 0, 1), 1), -1});
    s.batches.push_back({first, 3, static_cast<std::uint32_t>(s.materials.size() - 1)});
  }
  return s;
}

inline std::vector<gpu::PointLight> randomLightsIn(std::mt19937_64& rng, std::size_t n, const Aabb& b) {
  std::vector<gpu::PointLight> out;
  const float size = glm::length(b.max - b.min);
  for (std::size_t i = 0; i < n; ++i) {
    const glm::vec3 p(uniformIn(rng, b.min.x, b.max.x), uniformIn(rng, b.min.y, b.max.y),
                      uniformIn(rng, b.min.z, b.max.z));
    out.push_back(makeLight(p, uniformIn(rng, 0.1f, 1.0f) * size,
                            glm::vec3(uniformIn(rng, 0, 1), uniformIn(rng, 0, 1), uniformIn(rng, 0, 1))));
  }
  return out;
}

}  // namespace ml::test
