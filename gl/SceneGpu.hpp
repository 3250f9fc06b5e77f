#pragma once
// The scene's geometry, materials and textures on the GL side; draw() issues
// one indexed draw per batch, setting the material uniforms of `program`.
#include <epoxy/gl.h>

#include <vector>

#include "gl/ShaderProgram.hpp"
#include "host/scene/Scene.hpp"

namespace ml {

class SceneGpu {
 public:
  explicit SceneGpu(const Scene& scene);
  ~SceneGpu();
  SceneGpu(const SceneGpu&) = delete;
  SceneGpu& operator=(const SceneGpu&) = delete;
  // materials=false: geometry only (depth pre-pass).
  void draw(const ShaderProgram& program, bool materials) const;
  std::size_t triangleCount() const { return index_count_ / 3; }

 private:
  GLuint vao_ = 0, vbo_ = 0, ibo_ = 0;
  std::size_t index_count_ = 0;
  std::vector<GLuint> textures_;
  std::vector<DrawBatch> batches_;
  std::vector<Material> materials_;
};

}  // namespace ml
