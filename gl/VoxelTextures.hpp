#pragma once
// GL 3D textures of the voxel volumes, for hardware trilinear filtering within
// and between levels when cones sample them. unpack() copies each level l of
// the radiance volume (host/shared/voxel_types.h: one float4 per voxel at
// voxel_level_offset(), premultiplied) into level l of a mip-mapped RGBA16F 3D
// texture with a GL compute shader (gl/shaders/voxel_unpack.comp, one dispatch
// per level), and, when an anisotropic buffer is given, into 6 textures, one
// per direction (ML_VOXEL_DIR_*): their level 0 is the isotropic level 0 (a
// voxel looks the same from every side), levels >= 1 come from the
// anisotropic volume. One GL pass, `vct-textures`. Textures are reallocated
// when the grid's edge or levels change, otherwise reused. The buffers must
// be owned by GL (released after the kernels); a buffer larger than the GL's
// shader storage block limit is a UserError (the shader indexes it whole).
#include <array>

#include "gl/GlPassTimer.hpp"
#include "gl/ShaderProgram.hpp"
#include "host/shared/voxel_types.h"

namespace ml {

class VoxelTextures {
 public:
  VoxelTextures();
  ~VoxelTextures();
  VoxelTextures(const VoxelTextures&) = delete;
  VoxelTextures& operator=(const VoxelTextures&) = delete;

  // `aniso` is 0 when the volume is isotropic (directions are then left alone).
  void unpack(const gpu::VoxelGridParams& grid, GLuint radiance, GLuint aniso, GlPassTimer* timer);

  GLuint radiance() const { return radiance_; }
  GLuint direction(unsigned dir) const { return dirs_[dir]; }  // 0 until an anisotropic unpack

 private:
  void allocate(const gpu::VoxelGridParams& grid, bool aniso);
  // Level `level` of `texture` from `buffer`, whose element `offset` is the level's first voxel.
  void unpackLevel(GLuint buffer, std::size_t offset, GLuint texture, unsigned edge, unsigned level);

  ShaderProgram program_;
  GLuint radiance_ = 0;
  std::array<GLuint, ML_VOXEL_DIRECTIONS> dirs_{};
  unsigned edge_ = 0, levels_ = 0;
};

}  // namespace ml
