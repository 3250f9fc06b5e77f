#include "host/tiled/TiledAssigner.hpp"

#include "gl/GlCheck.hpp"
#include "gl/ShaderProgram.hpp"
#include "host/assign/LightFootprint.hpp"
#include "host/cl/ClRuntime.hpp"
#include "host/shared/shading_bindings.h"

namespace ml {

unsigned autoTileSize(double light_pixels) { return tileForLights(light_pixels, kTilePerLightPixel, 8u, 16u); }

TiledAssigner::TiledAssigner(ClRuntime& rt, unsigned tile_size, TileDepthMode mode, KernelShape shape)
    : rt_(rt), tile_size_(tile_size), mode_(mode), shape_(shape) {
  // The kernels are built now, for a build failure or a bad size to show at once.
  useTile(tile_size ? tile_size : autoTileSize(0.0));
  grid_ = std::make_unique<SharedBuffer>(rt, 4096 * sizeof(gpu::LightRange), "tile light grid");
  indices_ = std::make_unique<SharedBuffer>(rt, 65536 * sizeof(std::uint32_t), "tile light indices");
}

void TiledAssigner::useTile(unsigned tile_size) {
  // One culler at a time: the light size changes slowly, and a switch rebuilds
  // the kernels from the program cache.
  if (!culler_ || culler_->tileGrid().tile_size != tile_size)
    culler_ = std::make_unique<TileLightCuller>(rt_, tile_size, mode_, shape_);
}

void TiledAssigner::assign(const FrameInputs& in) {
  cl::CommandQueue& q = rt_.queue();
  if (!tile_size_) {
    light_pixels_ = coveringLightPixels(in.host_lights, in.camera_params);
    useTile(autoTileSize(light_pixels_));
  }
  in.lights.acquireForCl(q, ClAccess::Read);
  if (in.depth) in.depth->acquireForCl(q, ClAccess::Read);
  const std::uint32_t total =
      culler_->count(q, in.lights.cl(), in.light_count, in.camera_params, in.depth ? &in.depth->cl() : nullptr,
                    &in.cl_timer);
  last_total_ = total;
  // GL owns the output buffers while they grow; CL takes them for the fill.
  grid_->reserve(culler_->tileGrid().count() * sizeof(gpu::LightRange));
  indices_->reserve(std::size_t(total) * sizeof(std::uint32_t));
  grid_->acquireForCl(q, ClAccess::Write);
  indices_->acquireForCl(q, ClAccess::Write);
  culler_->fill(q, in.lights.cl(), in.light_count, in.camera_params, grid_->cl(), indices_->cl(), &in.cl_timer);
  indices_->releaseToGl(q);
  grid_->releaseToGl(q);
  if (in.depth) in.depth->releaseToGl(q);
  in.lights.releaseToGl(q);
}

ShaderDefines TiledAssigner::shaderDefines() const {
  return {{"TILE_SIZE", std::to_string(culler_->tileGrid().tile_size) + "u"}};
}

void TiledAssigner::bindForShading(const ShaderProgram& program) const {
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, ML_BINDING_TILED_INDICES, indices_->gl());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, ML_BINDING_TILED_GRID, grid_->gl());
  program.set("u_tiles_x", culler_->tileGrid().tilesX());
  glCheck("binding the tile light grid");
}

std::size_t TiledAssigner::memoryBytes() const {
  return std::size_t(culler_->tileGrid().count()) * sizeof(gpu::LightRange) +
         std::size_t(last_total_) * sizeof(std::uint32_t) + culler_->scratchBytes();
}

std::vector<std::pair<std::string, double>> TiledAssigner::stats() const {
  return {{"tiles", double(culler_->tileGrid().count())},
          {"tile index entries", double(last_total_)},
          {"tile size", double(culler_->tileGrid().tile_size)},
          {"light radius px", light_pixels_}};
}

}  // namespace ml
