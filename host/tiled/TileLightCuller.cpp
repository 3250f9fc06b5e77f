#include "host/tiled/TileLightCuller.hpp"

#include <algorithm>
#include <stdexcept>
#include <string>

#include "host/cl/KernelArgs.hpp"
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
  rects_k_ = cl::Kernel(program_, "light_rects");
  mark_ = cl::Kernel(program_, "cull_mark");
  scatter_ = cl::Kernel(program_, "cull_scatter");
  write_grid_ = cl::Kernel(program_, "write_grid");
  // Buffers are never zero-sized: "no lights" is a normal frame.
  const auto& ctx = rt.context();
  rects_ = cl::Buffer(ctx, CL_MEM_READ_WRITE, 32);
  mask_words_ = cl::Buffer(ctx, CL_MEM_READ_WRITE, 16);
  mask_offsets_ = cl::Buffer(ctx, CL_MEM_READ_WRITE, 16);
  hit_masks_ = cl::Buffer(ctx, CL_MEM_READ_WRITE, 16);
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

std::size_t TileLightCuller::scratchBytes() const {
  return tile_capacity_ * (16 + 4 * 4) + light_capacity_ * (32 + 8) + mask_capacity_ * 4;
}

std::uint32_t TileLightCuller::count(cl::CommandQueue& q, const cl::Buffer& lights, std::uint32_t n,
                                     const gpu::CameraParams& cam, const cl::Buffer* depth, ClPassTimer* timer) {
  if (cam.width == 0 || cam.height == 0) throw std::logic_error("TileLightCuller: empty viewport");
  if (!depth && mode_ != TileDepthMode::None) throw std::logic_error("TileLightCuller: depth bounds need a depth buffer");
  ensureTiles(cam);
  const cl_uint tiles_x = grid_.tilesX(), tiles_y = grid_.tilesY(), n_tiles = grid_.count();
  auto ev = [&](const char* name) { return timer ? timer->next(name) : nullptr; };

  if (mode_ != TileDepthMode::None) {
    setArgs(bounds_, *depth, cam, tiles_x, tiles_y, tile_bounds_, tile_masks_);
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
    if (n > light_capacity_) {
      light_capacity_ = std::size_t(n) + n / 2;
      rects_ = cl::Buffer(rt_.context(), CL_MEM_READ_WRITE, light_capacity_ * 32);
      mask_words_ = cl::Buffer(rt_.context(), CL_MEM_READ_WRITE, light_capacity_ * 4);
      mask_offsets_ = cl::Buffer(rt_.context(), CL_MEM_READ_WRITE, light_capacity_ * 4);
    }
    setArgs(rects_k_, lights, n, cam, tiles_x, tiles_y, rects_, mask_words_);
    q.enqueueNDRangeKernel(rects_k_, cl::NullRange, cl::NDRange(n), cl::NullRange, nullptr, ev("tile-light-rects"));
    const std::uint32_t words = scan_.exclusiveTotal(q, mask_words_, mask_offsets_, n, timer);
    if (words > mask_capacity_) {
      mask_capacity_ = std::size_t(words) + words / 2;
      hit_masks_ = cl::Buffer(rt_.context(), CL_MEM_READ_WRITE, std::max<std::size_t>(16, mask_capacity_ * 4));
    }
    setArgs(mark_, rects_, n, cam, tiles_x, tile_bounds_, tile_masks_, mask_offsets_, hit_masks_, counts_);
    q.enqueueNDRangeKernel(mark_, cl::NullRange, cl::NDRange(n), cl::NullRange, nullptr, ev("tile-cull"));
  }
  return scan_.exclusiveTotal(q, counts_, offsets_, n_tiles, timer);
}

void TileLightCuller::fill(cl::CommandQueue& q, const cl::Buffer& lights, std::uint32_t n,
                           const gpu::CameraParams& cam, cl::Buffer& grid, cl::Buffer& indices, ClPassTimer* timer) {
  (void)lights;  // count() kept everything fill needs (the rectangles and hit masks)
  (void)cam;
  const cl_uint tiles_x = grid_.tilesX(), n_tiles = grid_.count();
  auto ev = [&](const char* name) { return timer ? timer->next(name) : nullptr; };
  if (n > 0) {
    q.enqueueFillBuffer(cursor_, cl_uint(0), 0, std::size_t(n_tiles) * sizeof(cl_uint));
    setArgs(scatter_, rects_, n, tiles_x, mask_offsets_, hit_masks_, offsets_, cursor_, indices);
    q.enqueueNDRangeKernel(scatter_, cl::NullRange, cl::NDRange(n), cl::NullRange, nullptr, ev("tile-scatter"));
  }
  setArgs(write_grid_, offsets_, counts_, n_tiles, grid);
  q.enqueueNDRangeKernel(write_grid_, cl::NullRange, cl::NDRange(n_tiles), cl::NullRange, nullptr, ev("tile-grid"));
}

}  // namespace ml
