#pragma once
// The second bounce of voxel cone tracing (--gi-bounces 2), after Crassin et
// al. 2011: every filled level-0 voxel gathers the light of the first
// bounce's volume through the same diffuse cones as the frame's pixels
// (gl/shaders/vct/vct_bounce.comp, vct_cones.glsl) and adds albedo *
// irradiance / pi to its injected radiance. Contract of run():
//  - reads the volume's accum (albedo, normal) and the textures of the
//    current volume (bound through ConeTraceSetup), writes level 0 of the
//    radiance buffer in place; GL must own both buffers;
//  - the caller then redoes the mips and textures (VctPipeline::refilter),
//    so the frame's cones see direct + one more bounce;
//  - a GL pass named `vct-bounce`. Not thread-safe; needs the GL context.
#include "gl/GlPassTimer.hpp"
#include "gl/ShaderProgram.hpp"
#include "host/vct/ConeTracing.hpp"
#include "host/vct/VoxelVolume.hpp"

namespace ml::vct {

class VoxelBouncePass {
 public:
  VoxelBouncePass();
  void run(VoxelVolume& volume, const ConeTraceSetup& cones, GlPassTimer* timer);

 private:
  ShaderProgram program_;
};

}  // namespace ml::vct
