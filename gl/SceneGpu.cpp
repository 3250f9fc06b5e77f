#include "gl/SceneGpu.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>

#include "gl/GlCheck.hpp"
#include "host/shared/shading_bindings.h"

namespace ml {

SceneGpu::SceneGpu(const Scene& scene) : batches_(scene.batches), materials_(scene.materials) {
  glCreateVertexArrays(1, &vao_);
  glCreateBuffers(1, &vbo_);
  glCreateBuffers(1, &ibo_);
  // Zero-sized storage is an error in GL, so empty scenes get one byte with no data
  // (passing the data pointer with a padded size would read past the vector).
  const auto upload = [](GLuint buffer, const void* data, std::size_t bytes) {
    glNamedBufferStorage(buffer, static_cast<GLsizeiptr>(std::max<std::size_t>(bytes, 1)),
                         bytes ? data : nullptr, 0);
  };
  upload(vbo_, scene.vertices.data(), scene.vertices.size() * sizeof(Vertex));
  upload(ibo_, scene.indices.data(), scene.indices.size() * sizeof(std::uint32_t));
  index_count_ = scene.indices.size();
  glVertexArrayVertexBuffer(vao_, 0, vbo_, 0, sizeof(Vertex));
  glVertexArrayElementBuffer(vao_, ibo_);
  const GLuint offsets[3] = {offsetof(Vertex, position), offsetof(Vertex, normal), offsetof(Vertex, uv)};
  const GLint sizes[3] = {3, 3, 2};
  for (GLuint a = 0; a < 3; ++a) {
    glEnableVertexArrayAttrib(vao_, a);
    glVertexArrayAttribFormat(vao_, a, sizes[a], GL_FLOAT, GL_FALSE, offsets[a]);
    glVertexArrayAttribBinding(vao_, a, 0);
  }
  for (const Texture& t : scene.textures) {
    GLuint tex = 0;
    glCreateTextures(GL_TEXTURE_2D, 1, &tex);
    const int levels = 1 + static_cast<int>(std::log2(std::max(1, std::max(t.width, t.height))));
    glTextureStorage2D(tex, levels, GL_RGBA8, t.width, t.height);
    // Scene textures are stored top row first; glTF UV (0,0) is the top-left, so
    // uploading rows in order and sampling with v as-is matches glTF.
    glTextureSubImage2D(tex, 0, 0, 0, t.width, t.height, GL_RGBA, GL_UNSIGNED_BYTE, t.rgba8.data());
    glGenerateTextureMipmap(tex);
    glTextureParameteri(tex, GL_TEXTURE_MIN_FILTER, GL_LINEAR_MIPMAP_LINEAR);
    glTextureParameteri(tex, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    glTextureParameteri(tex, GL_TEXTURE_WRAP_S, GL_REPEAT);
    glTextureParameteri(tex, GL_TEXTURE_WRAP_T, GL_REPEAT);
    textures_.push_back(tex);
  }
  glCheck("uploading the scene");
}

SceneGpu::~SceneGpu() {
  if (!textures_.empty()) glDeleteTextures(static_cast<GLsizei>(textures_.size()), textures_.data());
  glDeleteBuffers(1, &vbo_);
  glDeleteBuffers(1, &ibo_);
  glDeleteVertexArrays(1, &vao_);
}

void SceneGpu::draw(const ShaderProgram& program, bool materials) const {
  glBindVertexArray(vao_);
  for (const DrawBatch& b : batches_) {
    if (materials) {
      const Material& m = materials_.at(b.material);
      program.set4("u_base_color", m.base_color.r, m.base_color.g, m.base_color.b, m.base_color.a);
      const bool has_tex = m.base_color_texture >= 0 && m.base_color_texture < static_cast<int>(textures_.size());
      program.set("u_has_texture", has_tex ? 1 : 0);
      if (has_tex) glBindTextureUnit(ML_UNIT_BASE_TEXTURE, textures_[static_cast<size_t>(m.base_color_texture)]);
    }
    glDrawElements(GL_TRIANGLES, static_cast<GLsizei>(b.index_count), GL_UNSIGNED_INT,
                   reinterpret_cast<const void*>(static_cast<std::uintptr_t>(b.first_index) * sizeof(std::uint32_t)));
  }
  glBindVertexArray(0);
}

}  // namespace ml
