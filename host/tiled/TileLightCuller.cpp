#include "host/tiled/TileLightCuller.hpp"

#include <algorithm>
#include <numeric>
#include <stdexcept>
#include <string>
#include <vector>

#include "host/cl/KernelArgs.hpp"
#include "host/cl/ProgramBuilder.hpp"
#include "host/util/Error.hpp"

namespace ml {

namespace {
constexpr std::size_t kMarkWg = 256;  // MARK_WG in the kernel: most items of a cull_mark_wg group
constexpr std::uint64_t kMax32 = 0xffffffffull;
}  // namespace

TileLightCuller::TileLightCuller(ClRuntime& rt, unsigned tile_size, TileDepthMode mode, KernelShape shape)
    : rt_(rt), mode_(mode), shape_(resolveKernelShape(rt.info(), shape)), scan_(rt, compute::Options{shape_}) {
  if (tile_size < 1 || tile_size > kMaxTileSize)
    throw UserError("--tile: tile size must be 1.." + std::to_string(kMaxTileSize) + ", got " + std::to_string(tile_size));
  grid_.tile_size = tile_size;
  // GPU shape: a work-group per tile (local atomics), a work-item per (light,
  // tile) pair; on CPU devices a work-item walking its tile or its light's
  // rectangle is a plain loop (see the PoCL notes).
  gpu_shape_ = shape_ == KernelShape::GpuWorkGroup;
  program_ = rt.programs().build("tiled_light_culling.cl", {{"TILE_SIZE", std::to_string(tile_size)},
                                                            {"DEPTH_MODE", std::to_string(static_cast<int>(mode))}});
  bounds_ = cl::Kernel(program_, gpu_shape_ ? "tile_depth_bounds_wg" : "tile_depth_bounds");
  rects_k_ = cl::Kernel(program_, "light_rects");
  mark_ = cl::Kernel(program_, gpu_shape_ ? "cull_mark_wg" : "cull_mark");
  scatter_ = cl::Kernel(program_, gpu_shape_ ? "cull_scatter_wg" : "cull_scatter");
  write_grid_ = cl::Kernel(program_, "write_grid");
  const cl::Device& dev = rt.device();
  const DeviceInfo& info = rt.info();
  rects_local_ = elementLocalSize(rects_k_, dev, info);
  grid_local_ = elementLocalSize(write_grid_, dev, info);
  element_local_ = elementLocalSize(scatter_, dev, info);
  if (gpu_shape_) {
    bounds_local_ = fitLocalSize(bounds_, dev, std::min<std::size_t>(std::size_t(tile_size) * tile_size, 256), 1, 0,
                                 "tile_depth_bounds_wg");
    mark_local_ = fitLocalSize(mark_, dev, kMarkWg, 32, 0, "cull_mark_wg");
  } else {
    bounds_local_ = elementLocalSize(bounds_, dev, info);
    mark_local_ = elementLocalSize(mark_, dev, info);
  }
  // Buffers are never zero-sized: "no lights" is a normal frame.
  rects_ = checkedBuffer(rt, CL_MEM_READ_WRITE, 32, "tiled culling");
  mask_words_ = checkedBuffer(rt, CL_MEM_READ_WRITE, 16, "tiled culling");
  mask_offsets_ = checkedBuffer(rt, CL_MEM_READ_WRITE, 16, "tiled culling");
  hit_masks_ = checkedBuffer(rt, CL_MEM_READ_WRITE, 16, "tiled culling");
}

void TileLightCuller::ensureTiles(const gpu::CameraParams& cam) {
  grid_.width = cam.width;
  grid_.height = cam.height;
  const std::size_t n = grid_.count();
  if (n <= tile_capacity_) return;
  tile_capacity_ = n;
  tile_bounds_ = checkedBuffer(rt_, CL_MEM_READ_WRITE, n * sizeof(cl_float4), "tile depth bounds");
  tile_masks_ = checkedBuffer(rt_, CL_MEM_READ_WRITE, n * sizeof(cl_uint), "tile depth masks");
  counts_ = checkedBuffer(rt_, CL_MEM_READ_WRITE, n * sizeof(cl_uint), "tile light counts");
  offsets_ = checkedBuffer(rt_, CL_MEM_READ_WRITE, n * sizeof(cl_uint), "tile light offsets");
  cursor_ = checkedBuffer(rt_, CL_MEM_READ_WRITE, n * sizeof(cl_uint), "tile light cursors");
}

void TileLightCuller::ensureLights(std::uint32_t n) {
  if (n <= light_capacity_) return;
  light_capacity_ = std::size_t(n) + n / 2;
  rects_ = checkedBuffer(rt_, CL_MEM_READ_WRITE, light_capacity_ * 32, "tiled culling light rectangles");
  mask_words_ = checkedBuffer(rt_, CL_MEM_READ_WRITE, light_capacity_ * 4, "tiled culling mask sizes");
  mask_offsets_ = checkedBuffer(rt_, CL_MEM_READ_WRITE, light_capacity_ * 4, "tiled culling mask offsets");
}

std::size_t TileLightCuller::scratchBytes() const {
  return tile_capacity_ * (16 + 4 * 4) + light_capacity_ * (32 + 8) + mask_capacity_ * 4;
}

// The scan wraps mod 2^32. When n values of at most per_item_max each could
// sum past that, the values are read back and summed in 64 bits (rare: lights
// x tiles beyond 2^32); otherwise the wrapped total is the total.
std::uint64_t TileLightCuller::exactTotal(cl::CommandQueue& q, const cl::Buffer& values, std::size_t n,
                                          std::uint32_t wrapped, std::uint64_t per_item_max) const {
  if (std::uint64_t(n) * per_item_max <= kMax32) return wrapped;
  std::vector<std::uint32_t> host(n);
  q.enqueueReadBuffer(values, CL_TRUE, 0, n * 4, host.data());
  return std::accumulate(host.begin(), host.end(), std::uint64_t(0));
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
    // GPU: one work-group per tile; CPU: one work-item per tile.
    launch1d(q, bounds_, gpu_shape_ ? std::size_t(n_tiles) * bounds_local_ : n_tiles, bounds_local_,
             ev("tile-depth-bounds"));
  }
  q.enqueueFillBuffer(counts_, cl_uint(0), 0, std::size_t(n_tiles) * sizeof(cl_uint));
  words_ = 0;
  if (n > 0) {
    ensureLights(n);
    setArgs(rects_k_, lights, n, cam, tiles_x, tiles_y, rects_, mask_words_);
    launch1d(q, rects_k_, n, rects_local_, ev("tile-light-rects"));
    const std::uint32_t wrapped = scan_.exclusiveTotal(q, mask_words_, mask_offsets_, n, timer);
    const std::uint64_t words = exactTotal(q, mask_words_, n, wrapped, (std::uint64_t(n_tiles) + 31) / 32);
    if (words > kMax32)
      throw UserError("tiled culling: the lights' tile masks need " + std::to_string(words) +
                      " words, more than 32-bit offsets reach (fewer --lights, a larger --tile or a smaller --size)");
    words_ = std::uint32_t(words);
    if (words_ > mask_capacity_) {
      mask_capacity_ = std::min<std::size_t>(std::size_t(words_) + words_ / 2, rt_.info().max_alloc_size / 4);
      mask_capacity_ = std::max<std::size_t>(mask_capacity_, words_);
      hit_masks_ = cl::Buffer();  // release first: the old and new buffer need not coexist
      hit_masks_ = checkedBuffer(rt_, CL_MEM_READ_WRITE, mask_capacity_ * 4, "tiled culling hit masks");
    }
    if (gpu_shape_) {
      setArgs(mark_, rects_, n, words_, cam, tiles_x, tile_bounds_, tile_masks_, mask_offsets_, hit_masks_, counts_);
      launch1d(q, mark_, std::size_t(words_) * 32, mark_local_, ev("tile-cull"));
    } else {
      setArgs(mark_, rects_, n, cam, tiles_x, tile_bounds_, tile_masks_, mask_offsets_, hit_masks_, counts_);
      launch1d(q, mark_, n, mark_local_, ev("tile-cull"));
    }
  }
  const std::uint32_t wrapped = scan_.exclusiveTotal(q, counts_, offsets_, n_tiles, timer);
  const std::uint64_t total = exactTotal(q, counts_, n_tiles, wrapped, n);
  if (total > kMax32 || total * 4 > rt_.info().max_alloc_size)
    throw UserError("tiled culling: the tile light lists hold " + std::to_string(total) +
                    " entries, more than 32-bit offsets or one device allocation hold (fewer --lights, a smaller "
                    "--size or --tile-depth minmax)");
  return std::uint32_t(total);
}

void TileLightCuller::fill(cl::CommandQueue& q, const cl::Buffer& lights, std::uint32_t n,
                           const gpu::CameraParams& cam, cl::Buffer& grid, cl::Buffer& indices, ClPassTimer* timer) {
  (void)lights;  // count() kept everything fill needs (the rectangles and hit masks)
  (void)cam;
  const cl_uint tiles_x = grid_.tilesX(), n_tiles = grid_.count();
  auto ev = [&](const char* name) { return timer ? timer->next(name) : nullptr; };
  if (n > 0) {
    q.enqueueFillBuffer(cursor_, cl_uint(0), 0, std::size_t(n_tiles) * sizeof(cl_uint));
    if (gpu_shape_) {
      setArgs(scatter_, rects_, n, words_, tiles_x, mask_offsets_, hit_masks_, offsets_, cursor_, indices);
      launch1d(q, scatter_, std::size_t(words_) * 32, element_local_, ev("tile-scatter"));
    } else {
      setArgs(scatter_, rects_, n, tiles_x, mask_offsets_, hit_masks_, offsets_, cursor_, indices);
      launch1d(q, scatter_, n, element_local_, ev("tile-scatter"));
    }
  }
  setArgs(write_grid_, offsets_, counts_, n_tiles, grid);
  launch1d(q, write_grid_, n_tiles, grid_local_, ev("tile-grid"));
}

}  // namespace ml
