#pragma once
// GL 3D textures of the voxel volumes, for hardware trilinear filtering within
// and between levels when cones sample them. unpack() uploads each level l of
// the radiance volume (host/shared/voxel_types.h: one float4 per voxel at
// voxel_level_offset(), premultiplied) into level l of a mip-mapped RGBA16F 3D
// texture, and, when an anisotropic buffer is given, into 6 textures, one per
// direction (ML_VOXEL_DIR_*): their level 0 is a copy of the isotropic level 0
// (a voxel looks the same from every side), levels >= 1 come from the
// anisotropic volume. One GL pass, `vct-textures`. Textures are reallocated
// when the grid's edge or levels change, otherwise reused. The buffers must be
// owned by GL (released after the kernels).
//
// How, and why (measured on llvmpipe, 128^3 x 4 levels anisotropic, same run):
// each level is one glTextureSubImage3D from the volume buffer bound as the
// pixel unpack buffer (the driver converts float to half on the device side,
// no host copy), and the directions' level 0 is glCopyImageSubData of the
// isotropic texture's level 0: 45-48 ms. A compute shader storing every voxel
// with imageStore, one dispatch per level and texture, took 430-560 ms (6
// copies of level 0 through the shader were 3/4 of its voxels); the same
// shader with the texture copy for level 0, 115-128 ms.
#include <epoxy/gl.h>

#include <array>

#include "gl/GlPassTimer.hpp"
#include "host/shared/voxel_types.h"

namespace ml {

class VoxelTextures {
 public:
  VoxelTextures() = default;
  ~VoxelTextures();
  VoxelTextures(const VoxelTextures&) = delete;
  VoxelTextures& operator=(const VoxelTextures&) = delete;

  // `aniso` is 0 when the volume is isotropic (directions are then left alone).
  void unpack(const gpu::VoxelGridParams& grid, GLuint radiance, GLuint aniso, GlPassTimer* timer);

  GLuint radiance() const { return radiance_; }
  GLuint direction(unsigned dir) const { return dirs_[dir]; }  // 0 until an anisotropic unpack

 private:
  void allocate(const gpu::VoxelGridParams& grid, bool aniso);

  GLuint radiance_ = 0;
  std::array<GLuint, ML_VOXEL_DIRECTIONS> dirs_{};
  unsigned edge_ = 0, levels_ = 0;
  bool wrap_ = false;
};

}  // namespace ml
