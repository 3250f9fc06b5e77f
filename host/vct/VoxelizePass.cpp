#include "host/vct/VoxelizePass.hpp"

#include <bit>
#include <stdexcept>
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
    : options_(options),
      program_({"vct/voxelize.vert", "vct/voxelize.geom", "vct/voxelize.frag"}),
      clear_({"vct/voxel_clear.comp"}) {
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
                       GlPassTimer* timer, const vct::VoxelRegion& region) {
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
  vct::checkRegion(region, grid.edge);
  if (region.empty()) accum.reserve(bytes);
  else if (accum.used() < bytes)
    throw std::invalid_argument("VoxelizePass: a region needs the accumulation buffer of the whole grid");
  GlPassScope scope(timer, "vct-voxelize");
  clear(grid, accum, region);
  bindEmptyFramebuffer(grid.edge);
  program_.use();
  const auto& o = grid.origin_voxel_size;
  program_.set4("u_origin_voxel_size", o.x, o.y, o.z, o.w);
  program_.set("u_edge", grid.edge);
  program_.set("u_dilate", options_.dilate ? 1 : 0);
  const gpu::VoxelShift sh = gpu::voxel_shift(grid);
  program_.setU3("u_shift", sh.x, sh.y, sh.z);
  setRegion(program_, region);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, ML_BINDING_VOXELIZE_ACCUM, accum.gl());
  scene.draw(program_, true);
  glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT |
                  GL_CLIENT_MAPPED_BUFFER_BARRIER_BIT);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, ML_BINDING_VOXELIZE_ACCUM, 0);
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  glCheck("voxelizing the scene");
}

void VoxelizePass::clear(const gpu::VoxelGridParams& grid, SharedBuffer& accum, const vct::VoxelRegion& region) {
  const std::size_t edge = grid.edge;
  if (region.empty()) {
    glClearNamedBufferSubData(accum.gl(), GL_R32UI, 0, static_cast<GLsizeiptr>(edge * edge * edge * sizeof(gpu::VoxelAccum)),
                              GL_RED_INTEGER, GL_UNSIGNED_INT, nullptr);
  } else {
    clear_.use();
    clear_.set("u_edge", grid.edge);
    const gpu::VoxelShift sh = gpu::voxel_shift(grid);
    clear_.setU3("u_shift", sh.x, sh.y, sh.z);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, ML_BINDING_VOXELIZE_ACCUM, accum.gl());
    for (const vct::VoxelBox& b : region) {
      clear_.setU3("u_lo", b.lo[0], b.lo[1], b.lo[2]);
      clear_.setU3("u_size", b.hi[0] - b.lo[0], b.hi[1] - b.lo[1], b.hi[2] - b.lo[2]);
      glDispatchCompute((b.hi[0] - b.lo[0] + 3) / 4, (b.hi[1] - b.lo[1] + 3) / 4, (b.hi[2] - b.lo[2] + 3) / 4);
    }
  }
  glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
  glCheck("clearing the voxel accumulation buffer");
}

void VoxelizePass::setRegion(const ShaderProgram& p, const vct::VoxelRegion& region) const {
  int lo[3 * vct::kMaxRegionBoxes] = {}, hi[3 * vct::kMaxRegionBoxes] = {};
  for (std::size_t b = 0; b < region.size(); ++b)
    for (int a = 0; a < 3; ++a) {
      lo[3 * b + a] = static_cast<int>(region[b].lo[a]);
      hi[3 * b + a] = static_cast<int>(region[b].hi[a]);
    }
  p.set("u_box_count", static_cast<int>(region.size()));
  p.setI3v("u_box_lo", static_cast<int>(vct::kMaxRegionBoxes), lo);
  p.setI3v("u_box_hi", static_cast<int>(vct::kMaxRegionBoxes), hi);
}

}  // namespace ml
