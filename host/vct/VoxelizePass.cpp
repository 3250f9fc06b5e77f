#include "host/vct/VoxelizePass.hpp"

#include <bit>
#include <string>

#include "gl/GlCheck.hpp"
#include "host/shared/vct_bindings.h"
#include "host/util/Error.hpp"

namespace ml {

void checkVoxelGrid(const gpu::VoxelGridParams& grid) {
  const unsigned edge = grid.edge;
  if (edge == 0 || edge > ML_VOXEL_MAX_EDGE || !std::has_single_bit(edge))
    throw UserError("voxel grid edge " + std::to_string(edge) + " is not a power of two in 1.." +
                    std::to_string(ML_VOXEL_MAX_EDGE));
  const unsigned max_levels = static_cast<unsigned>(std::countr_zero(edge)) + 1;
  if (grid.levels < 1 || grid.levels > max_levels)
    throw UserError("voxel levels " + std::to_string(grid.levels) + " outside 1.." + std::to_string(max_levels) +
                    " for a grid of edge " + std::to_string(edge));
  if (!(grid.origin_voxel_size.w > 0.0f))
    throw UserError("voxel size must be positive, got " + std::to_string(grid.origin_voxel_size.w));
}

VoxelizePass::VoxelizePass(const VoxelizeOptions& options)
    : options_(options), program_({"vct/voxelize.vert", "vct/voxelize.geom", "vct/voxelize.frag"}) {
  glCreateFramebuffers(1, &fbo_);
  glCheck("creating the voxelization framebuffer");
}

VoxelizePass::~VoxelizePass() { glDeleteFramebuffers(1, &fbo_); }

// Rasterisation without attachments: the fragments only write the SSBO.
void VoxelizePass::bindEmptyFramebuffer(unsigned edge) {
  if (edge != fbo_edge_) {
    glNamedFramebufferParameteri(fbo_, GL_FRAMEBUFFER_DEFAULT_WIDTH, static_cast<GLint>(edge));
    glNamedFramebufferParameteri(fbo_, GL_FRAMEBUFFER_DEFAULT_HEIGHT, static_cast<GLint>(edge));
    fbo_edge_ = edge;
  }
  glBindFramebuffer(GL_FRAMEBUFFER, fbo_);
  glViewport(0, 0, static_cast<GLsizei>(edge), static_cast<GLsizei>(edge));
  glDisable(GL_DEPTH_TEST);
  glDisable(GL_CULL_FACE);
  glDisable(GL_BLEND);
  glDisable(GL_MULTISAMPLE);
}

void VoxelizePass::run(const SceneGpu& scene, const gpu::VoxelGridParams& grid, SharedBuffer& accum,
                       GlPassTimer* timer) {
  checkVoxelGrid(grid);
  const std::size_t edge = grid.edge;
  const std::size_t bytes = edge * edge * edge * sizeof(gpu::VoxelAccum);
  // The shader indexes one unsized SSBO array: past the driver's block limit
  // its writes would be dropped without an error.
  GLint64 max_block = 0;
  glGetInteger64v(GL_MAX_SHADER_STORAGE_BLOCK_SIZE, &max_block);
  if (max_block > 0 && bytes > static_cast<std::size_t>(max_block))
    throw UserError("voxel grid edge " + std::to_string(edge) + " needs " + std::to_string(bytes >> 20) +
                    " MiB of voxel sums, more than this GL's shader storage block limit (" +
                    std::to_string(max_block >> 20) + " MiB)");
  accum.reserve(bytes);
  GlPassScope scope(timer, "vct-voxelize");
  glClearNamedBufferSubData(accum.gl(), GL_R32UI, 0, static_cast<GLsizeiptr>(bytes), GL_RED_INTEGER,
                            GL_UNSIGNED_INT, nullptr);
  glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
  glCheck("clearing the voxel accumulation buffer");
  bindEmptyFramebuffer(grid.edge);
  program_.use();
  const auto& o = grid.origin_voxel_size;
  program_.set4("u_origin_voxel_size", o.x, o.y, o.z, o.w);
  program_.set("u_edge", grid.edge);
  program_.set("u_dilate", options_.dilate ? 1 : 0);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, ML_BINDING_VOXELIZE_ACCUM, accum.gl());
  scene.draw(program_, true);
  glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT |
                  GL_CLIENT_MAPPED_BUFFER_BARRIER_BIT);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, ML_BINDING_VOXELIZE_ACCUM, 0);
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  glCheck("voxelizing the scene");
}

}  // namespace ml
