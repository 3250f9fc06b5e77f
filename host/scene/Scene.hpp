#pragma once
// Triangle geometry ready for upload: all meshes flattened to world space
// (node transforms applied, normals transformed by the inverse transpose and
// generated where missing), grouped in draw batches by material.
#include <glm/glm.hpp>

#include <cstdint>
#include <string>
#include <vector>

#include "host/scene/GltfLights.hpp"
#include "host/shared/gpu_types.h"

namespace ml {

struct Vertex {
  glm::vec3 position;
  glm::vec3 normal;
  glm::vec2 uv;
};
static_assert(sizeof(Vertex) == 32, "Vertex is uploaded as-is");

struct Texture {
  int width = 0;
  int height = 0;
  std::vector<std::uint8_t> rgba8;  // width * height * 4, row 0 = top; sRGB-encoded as in the file
};

struct Material {
  glm::vec4 base_color{1.0f};      // glTF baseColorFactor (linear)
  int base_color_texture = -1;     // index into Scene::textures or -1
};

struct DrawBatch {
  std::uint32_t first_index = 0;  // into Scene::indices
  std::uint32_t index_count = 0;
  std::uint32_t material = 0;     // into Scene::materials
};

struct Aabb {
  glm::vec3 min{1e30f};
  glm::vec3 max{-1e30f};
  void extend(const glm::vec3& p) {
    min = glm::min(min, p);
    max = glm::max(max, p);
  }
  bool empty() const { return min.x > max.x; }
};

struct Scene {
  std::string source;  // path it was loaded from (for messages)
  std::vector<Vertex> vertices;
  std::vector<std::uint32_t> indices;  // triangles
  std::vector<DrawBatch> batches;
  std::vector<Material> materials;     // never empty after loading (default white)
  std::vector<Texture> textures;
  Aabb bounds;
  // The file's KHR_lights_punctual point lights (GltfLights.hpp), in node
  // order; empty when it has none. Not part of `bounds`.
  std::vector<gpu::PointLight> lights;
  std::size_t triangleCount() const { return indices.size() / 3; }
};

// Loads a .gltf or .glb (tinygltf): meshes (triangles; strips and fans are
// converted, points and lines skipped with a warning), the default scene's node
// hierarchy transforms (mirroring transforms get their winding flipped back),
// normals (generated when missing: per primitive, area-weighted average of the
// adjacent face normals), TEXCOORD_0, baseColor factor and texture (a texture
// that cannot be decoded is dropped with a warning), and the point lights of
// KHR_lights_punctual (GltfLights.hpp; light_threshold sets the radius of
// those without range; skipped lights are one warning line). Throws UserError
// naming the file for missing, unreadable or malformed input (malformed light
// entries included), or a scene without triangles.
Scene loadGltfScene(const std::string& path, float light_threshold = kDefaultLightThreshold);

}  // namespace ml
