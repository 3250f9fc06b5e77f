#pragma once
// A linked GL program built from gl/shaders/ files (embedded; see
// EmbeddedFiles.hpp). Each stage gets "#version 450 core", the host's defines,
// then the file with `#include "x.glsl"` lines expanded from gl/shaders/. Files
// and includes are named by their path under gl/shaders/ ("common/forward.frag",
// `#include "vct/vct_cones.glsl"`); a name that is no shader file there is read
// from host/shared/ (`#include "shading_bindings.h"`).
// Compile and link errors throw UserError with the file name and the log.
#include <epoxy/gl.h>

#include <string>
#include <utility>
#include <vector>

#include "host/assign/ShaderContract.hpp"  // ShaderDefines

namespace ml {

// Include aliases: {"lookup.glsl", "tiled/lookup_tiled.glsl"} makes `#include "lookup.glsl"`
// read tiled/lookup_tiled.glsl. This is how a technique plugs its light-list lookup
// into the shared forward/deferred shaders.
using ShaderAliases = std::vector<std::pair<std::string, std::string>>;

class ShaderProgram {
 public:
  ShaderProgram() = default;
  // stages: e.g. {"common/geometry.vert", "common/forward.frag"}; the stage comes from the extension
  // (.vert .frag .comp .geom).
  ShaderProgram(const std::vector<std::string>& files, const ShaderDefines& defines = {},
                const ShaderAliases& aliases = {});
  ~ShaderProgram();
  ShaderProgram(ShaderProgram&& o) noexcept : id_(std::exchange(o.id_, 0)), label_(std::move(o.label_)) {}
  ShaderProgram& operator=(ShaderProgram&& o) noexcept;
  ShaderProgram(const ShaderProgram&) = delete;
  ShaderProgram& operator=(const ShaderProgram&) = delete;

  GLuint id() const { return id_; }
  void use() const;
  // Uniform setters by name; a name the linker optimised away is ignored.
  void set(const char* name, int v) const;
  void set(const char* name, unsigned v) const;
  void set(const char* name, float v) const;
  void set(const char* name, const float* mat4) const;
  void set2(const char* name, float x, float y) const;
  void set3(const char* name, float x, float y, float z) const;
  void set4(const char* name, float x, float y, float z, float w) const;
  void setU2(const char* name, unsigned x, unsigned y) const;
  void setU3(const char* name, unsigned x, unsigned y, unsigned z) const;
  // Arrays: `count` elements of 3 ints, of 4 floats.
  void setI3v(const char* name, int count, const int* v) const;
  void set4v(const char* name, int count, const float* v) const;

 private:
  GLint loc(const char* name) const { return glGetUniformLocation(id_, name); }
  GLuint id_ = 0;
  std::string label_;
};

// Source of a shader file after include expansion (exposed for tests).
std::string expandShaderSource(const std::string& file, const ShaderDefines& defines,
                               const ShaderAliases& aliases = {});

}  // namespace ml
