#pragma once
// The buffers of voxel cone tracing, shared between GL (voxelization writes
// the accumulation buffer, cone tracing samples the volumes) and the OpenCL
// kernels (injection and mips), as SharedBuffers (gl/SharedBuffer.hpp):
//  - accum:     level 0, one VoxelAccum per voxel (what voxelization writes);
//  - radiance:  every level, one float4 per voxel at voxel_level_offset():
//               rgb = outgoing radiance premultiplied by opacity, a = opacity
//               (level 0: the lit voxel, opacity 1 or 0; levels >= 1: the
//               mips, kernels/vct/vct_mips.cl);
//  - anisotropic (only when the settings ask for it): levels >= 1, 6 float4
//               per voxel, premultiplied as above (voxel_aniso_index()).
// Buffers are sized once by the settings (checked with checkVoxelGrid());
// params() is the grid a caller fitted (fitVoxelGrid()) and may replace.
#include <memory>

#include "gl/SharedBuffer.hpp"
#include "host/cl/ClRuntime.hpp"
#include "host/vct/VoxelGrid.hpp"

namespace ml::vct {

class VoxelVolume {
 public:
  VoxelVolume(ClRuntime& rt, const VoxelGridSettings& settings, const gpu::VoxelGridParams& params);

  const VoxelGridSettings& settings() const { return settings_; }
  const gpu::VoxelGridParams& params() const { return params_; }
  void setParams(const gpu::VoxelGridParams& p);  // same edge and levels as the settings

  SharedBuffer& accum() { return *accum_; }
  SharedBuffer& radiance() { return *radiance_; }
  const SharedBuffer& accum() const { return *accum_; }        // read-only views (debug images)
  const SharedBuffer& radiance() const { return *radiance_; }
  SharedBuffer* anisotropic() { return aniso_.get(); }  // null unless settings().anisotropic
  const SharedBuffer* anisotropic() const { return aniso_.get(); }
  std::size_t bytes() const { return voxelBytes(settings_); }

 private:
  VoxelGridSettings settings_;
  gpu::VoxelGridParams params_;
  std::unique_ptr<SharedBuffer> accum_, radiance_, aniso_;
};

}  // namespace ml::vct
