#include "host/tiled/TileLightCuller.hpp"

#include <algorithm>
#include <stdexcept>
#include <string>

#include "host/cl/ProgramBuilder.hpp"
#include "host/util/Error.hpp"

namespace ml {

TileLightCuller::TileLightCuller(ClRuntime& rt, unsigned tile_size, TileDepthMode mode)
    : rt_(rt), mode_(mode), scan_(rt) {
  if (tile_size < 1 || tile_size > 256) throw UserError("--tile: tile size must be 1..256, got " + std::to_string(tile_size));
  grid_.tile_size = tile_size;
  // Kernel shape: a work-group per tile (local atomics) suits GPUs; on CPU
  // devices a work-item walking its tile is a plain loop (see the PoCL notes).
  gpu_shape_ = !rt.info().isCpu();
  program_ = rt.programs().build("tiled_light_culling.cl", {{"TILE_SIZE", std::to_string(tile_size)},
                                                            {"DEPTH_MODE", std::to_string(static_cast<int>(mode))}});
  bounds_ = cl::Kernel(program_, gpu_shape_ ? "tile_depth_bounds_wg" : "tile_depth_bounds");
  count_ = cl::Kernel(program_, "cull_count");
  fill_ = cl::Kernel(program_, "cull_fill");
  write_grid_ = cl::Kernel(program_, "write_grid");
  dummy_depth_ = cl::Buffer(rt.context(), CL_MEM_READ_ONLY, 16);
}

void TileLightCuller::ensureTiles(const gpu::CameraParams& cam) {
  grid_.width = cam.width;
  grid_.height = cam.height;
  const std::size_t n = grid_.count();
  if (n <= tile_capacity_) return;
  tile_capacity_ = n;
  const auto& ctx = rt_.context();
  tile_bounds_ = cl::Buffer(ctx, CL_MEM_READ_WRITE, n * sizeof(cl_float4));
  tile_masks_ = cl::Buffer(ctx, CL_MEM_READ_WRITE, n * sizeof(cl_uint));
  counts_ = cl::Buffer(ctx, CL_MEM_READ_WRITE, n * sizeof(cl_uint));
  offsets_ = cl::Buffer(ctx, CL_MEM_READ_WRITE, n * sizeof(cl_uint));
  cursor_ = cl::Buffer(ctx, CL_MEM_READ_WRITE, n * sizeof(cl_uint));
}

std::size_t TileLightCuller::scratchBytes() const { return tile_capacity_ * (16 + 4 * 4); }

std::uint32_t TileLightCuller::count(cl::CommandQueue& q, const cl::Buffer& lights, std::uint32_t n,
                                     const gpu::CameraParams& cam, const cl::Buffer* depth, ClPassTimer* timer) {
  if (cam.width == 0 || cam.height == 0) throw std::logic_error("TileLightCuller: empty viewport");
  if (!depth && mode_ != TileDepthMode::None) throw std::logic_error("TileLightCuller: depth bounds need a depth buffer");
  ensureTiles(cam);
  const cl_uint tiles_x = grid_.tilesX(), tiles_y = grid_.tilesY(), n_tiles = grid_.count();
  auto ev = [&](const char* name) { return timer ? timer->next(name) : nullptr; };

  if (mode_ != TileDepthMode::None) {
    bounds_.setArg(0, *depth);
    bounds_.setArg(1, cam);
    bounds_.setArg(2, tiles_x);
    bounds_.setArg(3, tiles_y);
    bounds_.setArg(4, tile_bounds_);
    bounds_.setArg(5, tile_masks_);
    if (gpu_shape_) {
      const std::size_t local = std::min<std::size_t>(
          {std::size_t(grid_.tile_size) * grid_.tile_size, rt_.info().max_work_group_size, 256});
      q.enqueueNDRangeKernel(bounds_, cl::NullRange, cl::NDRange(std::size_t(n_tiles) * local), cl::NDRange(local),
                             nullptr, ev("tile-depth-bounds"));
    } else {
      q.enqueueNDRangeKernel(bounds_, cl::NullRange, cl::NDRange(n_tiles), cl::NullRange, nullptr,
                             ev("tile-depth-bounds"));
    }
  }
  q.enqueueFillBuffer(counts_, cl_uint(0), 0, std::size_t(n_tiles) * sizeof(cl_uint));
  if (n > 0) {
    count_.setArg(0, lights);
    count_.setArg(1, n);
    count_.setArg(2, cam);
    count_.setArg(3, tiles_x);
    count_.setArg(4, tiles_y);
    count_.setArg(5, tile_bounds_);
    count_.setArg(6, tile_masks_);
    count_.setArg(7, counts_);
    q.enqueueNDRangeKernel(count_, cl::NullRange, cl::NDRange(n), cl::NullRange, nullptr, ev("tile-cull-count"));
  }
  return scan_.exclusiveTotal(q, counts_, offsets_, n_tiles, timer);
}

void TileLightCuller::fill(cl::CommandQueue& q, const cl::Buffer& lights, std::uint32_t n,
                           const gpu::CameraParams& cam, cl::Buffer& grid, cl::Buffer& indices, ClPassTimer* timer) {
  const cl_uint tiles_x = grid_.tilesX(), tiles_y = grid_.tilesY(), n_tiles = grid_.count();
  auto ev = [&](const char* name) { return timer ? timer->next(name) : nullptr; };
  if (n > 0) {
    q.enqueueFillBuffer(cursor_, cl_uint(0), 0, std::size_t(n_tiles) * sizeof(cl_uint));
    fill_.setArg(0, lights);
    fill_.setArg(1, n);
    fill_.setArg(2, cam);
    fill_.setArg(3, tiles_x);
    fill_.setArg(4, tiles_y);
    fill_.setArg(5, tile_bounds_);
    fill_.setArg(6, tile_masks_);
    fill_.setArg(7, offsets_);
    fill_.setArg(8, cursor_);
    fill_.setArg(9, indices);
    q.enqueueNDRangeKernel(fill_, cl::NullRange, cl::NDRange(n), cl::NullRange, nullptr, ev("tile-cull-fill"));
  }
  write_grid_.setArg(0, offsets_);
  write_grid_.setArg(1, counts_);
  write_grid_.setArg(2, n_tiles);
  write_grid_.setArg(3, grid);
  q.enqueueNDRangeKernel(write_grid_, cl::NullRange, cl::NDRange(n_tiles), cl::NullRange, nullptr, ev("tile-grid"));
}

}  // namespace ml
