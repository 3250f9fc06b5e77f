#include "host/tiled/TiledAssigner.hpp"

#include "gl/GlCheck.hpp"
#include "gl/ShaderProgram.hpp"
#include "host/cl/ClRuntime.hpp"
#include "host/shared/shading_bindings.h"

namespace ml {

TiledAssigner::TiledAssigner(ClRuntime& rt, unsigned tile_size, TileDepthMode mode, KernelShape shape)
    : rt_(rt), culler_(rt, tile_size, mode, shape) {
  grid_ = std::make_unique<SharedBuffer>(rt, 4096 * sizeof(gpu::LightRange), "tile light grid");
  indices_ = std::make_unique<SharedBuffer>(rt, 65536 * sizeof(std::uint32_t), "tile light indices");
}

void TiledAssigner::assign(const FrameInputs& in) {
  cl::CommandQueue& q = rt_.queue();
  in.lights.acquireForCl(q, ClAccess::Read);
  if (in.depth) in.depth->acquireForCl(q, ClAccess::Read);
  const std::uint32_t total =
      culler_.count(q, in.lights.cl(), in.light_count, in.camera_params, in.depth ? &in.depth->cl() : nullptr,
                    &in.cl_timer);
  last_total_ = total;
  // GL owns the output buffers while they grow; CL takes them for the fill.
  grid_->reserve(culler_.tileGrid().count() * sizeof(gpu::LightRange));
  indices_->reserve(std::size_t(total) * sizeof(std::uint32_t));
  grid_->acquireForCl(q, ClAccess::Write);
  indices_->acquireForCl(q, ClAccess::Write);
  culler_.fill(q, in.lights.cl(), in.light_count, in.camera_params, grid_->cl(), indices_->cl(), &in.cl_timer);
  indices_->releaseToGl(q);
  grid_->releaseToGl(q);
  if (in.depth) in.depth->releaseToGl(q);
  in.lights.releaseToGl(q);
}

ShaderDefines TiledAssigner::shaderDefines() const {
  return {{"TILE_SIZE", std::to_string(culler_.tileGrid().tile_size) + "u"}};
}

void TiledAssigner::bindForShading(const ShaderProgram& program) const {
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, ML_BINDING_TILED_INDICES, indices_->gl());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, ML_BINDING_TILED_GRID, grid_->gl());
  program.set("u_tiles_x", culler_.tileGrid().tilesX());
  glCheck("binding the tile light grid");
}

std::size_t TiledAssigner::memoryBytes() const {
  return std::size_t(culler_.tileGrid().count()) * sizeof(gpu::LightRange) +
         std::size_t(last_total_) * sizeof(std::uint32_t) + culler_.scratchBytes();
}

std::vector<std::pair<std::string, double>> TiledAssigner::stats() const {
  return {{"tiles", double(culler_.tileGrid().count())},
          {"tile index entries", double(last_total_)},
          {"tile size", double(culler_.tileGrid().tile_size)}};
}

}  // namespace ml
