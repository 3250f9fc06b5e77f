#include "host/vct/VoxelBouncePass.hpp"

#include "gl/GlCheck.hpp"
#include "host/shared/vct_bindings.h"
#include "host/shared/voxel_types.h"

namespace ml::vct {

static_assert(ML_VOXEL_ALBEDO_SCALE_GLSL == ML_VOXEL_ALBEDO_SCALE, "vct_bindings.h copies voxel_types.h's scale");

namespace {
constexpr unsigned kGroup = 64;  // vct_bounce.comp's local size
}  // namespace

VoxelBouncePass::VoxelBouncePass() : program_({"vct/vct_bounce.comp"}) {}

void VoxelBouncePass::run(VoxelVolume& volume, const ConeTraceSetup& cones, GlPassTimer* timer) {
  const gpu::VoxelGridParams& g = volume.params();
  const unsigned voxels = g.edge * g.edge * g.edge;
  GlPassScope scope(timer, "vct-bounce");
  program_.use();
  bindConeTracing(program_, cones);
  program_.set("u_edge_log2", log2Exact(g.edge));
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, ML_BINDING_BOUNCE_ACCUM, volume.accum().gl());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, ML_BINDING_BOUNCE_RADIANCE, volume.radiance().gl());
  glDispatchCompute((voxels + kGroup - 1) / kGroup, 1, 1);
  // The mips read the buffer through OpenCL next (acquisition waits for GL).
  glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT | GL_CLIENT_MAPPED_BUFFER_BARRIER_BIT);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, ML_BINDING_BOUNCE_ACCUM, 0);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, ML_BINDING_BOUNCE_RADIANCE, 0);
  glCheck("the voxels' second bounce");
}

}  // namespace ml::vct
