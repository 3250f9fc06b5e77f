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
constexpr std::size_t kTileSideBytes = 48;     // TileSide in the kernel
constexpr std::size_t kLanePad = 8;            // LANE_PAD in the kernel
constexpr std::size_t kLanePlanes = 9;         // LANE_PLANES in the kernel
constexpr cl_uint kBlockTiles = 8;             // BLOCK_TILES in the kernel
constexpr std::size_t kChunksPerUnit = 8;      // CPU shape: work-items per compute unit, for load balance
constexpr std::uint32_t kMinPerChunk = 64;     // ... but no fewer lights per work-item than this
constexpr std::size_t kMaxChunkCounters = std::size_t(1) << 24;  // chunks x tiles (64 MiB of counters)
constexpr std::uint64_t kLoopCapMargin = 60000;  // loop iterations a work-item may take where the device caps them

// Where the device ends a work-item's loops after 65,535 iterations in total
// (llvmpipe; Tuning::max_chunk is set there, tests/driver/driver_loop_cap_test.cpp),
// the most lights per chunk whose loops stay under the cap: the chunk's
// counter row (n_tiles iterations), then per light at most what a light
// covering the whole screen takes in mark_light (mask words, the cached
// columns, per row 19 per 8 tiles and the row, per block row its blocks'
// depth test) and in cull_scatter_chunked (a word and a bit per tile).
// Throws when not even one light fits.
std::uint32_t lightsWithinLoopCap(std::uint64_t tiles_x, std::uint64_t tiles_y) {
  const std::uint64_t n_tiles = tiles_x * tiles_y;
  const std::uint64_t block_tests =
      (tiles_y / kBlockTiles + 2) * (std::min<std::uint64_t>(tiles_x / kBlockTiles + 2, 64) + 1);
  const std::uint64_t per_light =
      n_tiles + n_tiles / 16 + 400 + (tiles_y + 1) * ((tiles_x / 8 + 2) * 19 + 1) + block_tests;
  if (n_tiles + 2 + per_light > kLoopCapMargin)
    throw UserError("tiled culling: the device ends a work-item's loops after 65,535 iterations, which a light "
                    "covering all " + std::to_string(n_tiles) + " tiles could pass in the CPU kernel shape (a larger "
                    "--tile, a smaller --size or --kernel-shape gpu)");
  return std::uint32_t((kLoopCapMargin - n_tiles - 1) / (per_light + 1));
}
// Auto on a device that caps a work-item's loops (llvmpipe: the CPU shape's
// tuning carries a max_chunk there) is the GPU shape, whose work-items walk a
// tile's share of the lights rather than a chunk of lights over the whole
// screen: a default run then never meets the CPU shape's refusal above
// (1080p at tile 16 fits one light per chunk there). Otherwise by device type.
KernelShape tiledShape(ClRuntime& rt, KernelShape requested) {
  const KernelShape s = resolveKernelShape(rt.info(), requested);
  if (requested != KernelShape::Auto || s != KernelShape::CpuChunked) return s;
  const compute::ComputeEnv env(rt);
  const bool capped = compute::resolveTuning(env, compute::Options{KernelShape::CpuChunked}).max_chunk != 0;
  return capped ? KernelShape::GpuWorkGroup : s;
}
}  // namespace

TileLightCuller::TileLightCuller(ClRuntime& rt, unsigned tile_size, TileDepthMode mode, KernelShape shape,
                                 TileCullAlgorithm algorithm)
    : rt_(rt), mode_(mode), shape_(tiledShape(rt, shape)), scan_(rt, compute::Options{shape_}) {
  if (tile_size < 1 || tile_size > kMaxTileSize)
    throw UserError("--tile: tile size must be 1.." + std::to_string(kMaxTileSize) + ", got " + std::to_string(tile_size));
  grid_.tile_size = tile_size;
  // GPU shape: a work-group per tile (local atomics), a work-item per (light,
  // tile) pair; on CPU devices a work-item walking its tile or its light's
  // rectangle is a plain loop (see the PoCL notes).
  gpu_shape_ = shape_ == KernelShape::GpuWorkGroup;
  const bool legacy = algorithm == TileCullAlgorithm::PairAtomics;
  chunked_ = !gpu_shape_ && !legacy;
  program_ = rt.programs().build("tiled/tiled_light_culling.cl", {{"TILE_SIZE", std::to_string(tile_size)},
                                                            {"DEPTH_MODE", std::to_string(static_cast<int>(mode))},
                                                            {"CULL_LEGACY", legacy ? "1" : "0"}});
  // A work-group per tile also in the CPU shape where one work-item's walk of
  // a tile's pixels (twice for the 2.5D mask) could pass the device's loop cap.
  const std::uint64_t pixels = std::uint64_t(tile_size) * tile_size;
  group_bounds_ = gpu_shape_ || (scan_.tuning().max_chunk && 2 * (pixels + tile_size) + 4 > kLoopCapMargin);
  bounds_ = cl::Kernel(program_, group_bounds_ ? "tile_depth_bounds_wg" : "tile_depth_bounds");
  rects_k_ = cl::Kernel(program_, "light_rects");
  mark_ = cl::Kernel(program_, gpu_shape_ ? "cull_mark_wg" : chunked_ ? "cull_mark_chunked" : "cull_mark");
  scatter_ = cl::Kernel(program_, gpu_shape_ ? "cull_scatter_wg" : chunked_ ? "cull_scatter_chunked" : "cull_scatter");
  write_grid_ = cl::Kernel(program_, "write_grid");
  sides_k_ = cl::Kernel(program_, "tile_sides");
  totals_k_ = cl::Kernel(program_, "tile_chunk_totals");
  bases_k_ = cl::Kernel(program_, "tile_chunk_bases");
  blocks_k_ = cl::Kernel(program_, "tile_blocks");
  const cl::Device& dev = rt.device();
  const DeviceInfo& info = rt.info();
  rects_local_ = elementLocalSize(rects_k_, dev, info);
  grid_local_ = elementLocalSize(write_grid_, dev, info);
  // The other per-tile, per-side and per-block kernels launch with it too.
  for (const cl::Kernel* k : {&sides_k_, &totals_k_, &bases_k_, &blocks_k_})
    grid_local_ = std::min(grid_local_, elementLocalSize(*k, dev, info));
  element_local_ = elementLocalSize(scatter_, dev, info);
  if (group_bounds_)
    bounds_local_ = fitLocalSize(bounds_, dev, std::min<std::size_t>(std::size_t(tile_size) * tile_size, 256), 1, 0,
                                 "tile_depth_bounds_wg");
  else
    bounds_local_ = elementLocalSize(bounds_, dev, info);
  if (gpu_shape_) {
    mark_local_ = fitLocalSize(mark_, dev, kMarkWg, 32, 0, "cull_mark_wg");
  } else {
    // Chunked: a work-item per chunk of lights, local size 1 (a plain loop on PoCL).
    mark_local_ = chunked_ ? 1 : elementLocalSize(mark_, dev, info);
    if (chunked_) element_local_ = 1;
  }
  // Buffers are never zero-sized: "no lights" is a normal frame.
  rects_ = checkedBuffer(rt, CL_MEM_READ_WRITE, 32, "tiled culling");
  mask_words_ = checkedBuffer(rt, CL_MEM_READ_WRITE, 16, "tiled culling");
  mask_offsets_ = checkedBuffer(rt, CL_MEM_READ_WRITE, 16, "tiled culling");
  hit_masks_ = checkedBuffer(rt, CL_MEM_READ_WRITE, 16, "tiled culling");
  chunk_counts_ = checkedBuffer(rt, CL_MEM_READ_WRITE, 16, "tiled culling");
  blocks_lo_ = checkedBuffer(rt, CL_MEM_READ_WRITE, 16, "tiled culling");
  blocks_hi_ = checkedBuffer(rt, CL_MEM_READ_WRITE, 16, "tiled culling");
}

void TileLightCuller::ensureTiles(const gpu::CameraParams& cam) {
  grid_.width = cam.width;
  grid_.height = cam.height;
  const std::size_t n = grid_.count();
  if (n <= tile_capacity_) return;
  tile_capacity_ = n;
  tile_bounds_ = checkedBuffer(rt_, CL_MEM_READ_WRITE, n * sizeof(cl_float4), "tile depth bounds");
  tile_masks_ = checkedBuffer(rt_, CL_MEM_READ_WRITE, n * sizeof(cl_uint), "tile depth masks");
  tile_boxes_ = checkedBuffer(rt_, CL_MEM_READ_WRITE, n * sizeof(cl_float4), "tile depth boxes");
  tile_lanes_ =
      checkedBuffer(rt_, CL_MEM_READ_WRITE, (n + kLanePad) * kLanePlanes * sizeof(cl_float), "tile depth lanes");
  counts_ = checkedBuffer(rt_, CL_MEM_READ_WRITE, n * sizeof(cl_uint), "tile light counts");
  offsets_ = checkedBuffer(rt_, CL_MEM_READ_WRITE, n * sizeof(cl_uint), "tile light offsets");
  cursor_ = checkedBuffer(rt_, CL_MEM_READ_WRITE, n * sizeof(cl_uint), "tile light cursors");
}

// CPU shape: as many chunks as keep the compute units balanced, each holding
// at least one light (the kernels leave the rows of empty chunks unwritten)
// and, past kMinPerChunk lights, no fewer than that; where the device caps
// loops, no more than lightsWithinLoopCap().
void TileLightCuller::ensureChunks(std::uint32_t n, std::size_t n_tiles) {
  const std::size_t max_chunks = kMaxChunkCounters / std::max<std::size_t>(n_tiles, 1);
  const std::size_t most = std::max<std::size_t>(
      1, std::min<std::size_t>(std::size_t(std::max<cl_uint>(rt_.info().compute_units, 1)) * kChunksPerUnit,
                               max_chunks));
  const std::size_t want = std::clamp<std::size_t>(n / kMinPerChunk, 1, most);
  per_chunk_ = std::uint32_t((std::uint64_t(n) + want - 1) / want);
  if (scan_.tuning().max_chunk) per_chunk_ = std::min(per_chunk_, lightsWithinLoopCap(grid_.tilesX(), grid_.tilesY()));
  chunks_ = std::uint32_t((std::uint64_t(n) + per_chunk_ - 1) / per_chunk_);
  // tile_chunk_totals and tile_chunk_bases loop over the chunks per tile.
  const bool capped = scan_.tuning().max_chunk && chunks_ > kLoopCapMargin;
  if (capped || chunks_ > std::max<std::size_t>(max_chunks, 1))
    throw UserError("tiled culling: " + std::to_string(n) + " lights in chunks short enough for the device's loop "
                    "cap need " + std::to_string(chunks_) + " chunks, more than its loop cap or " +
                    std::to_string(kMaxChunkCounters) + " tile counters allow (fewer --lights, a larger --tile or "
                    "--kernel-shape gpu)");
  const std::size_t need = std::size_t(chunks_) * n_tiles;
  if (need <= chunk_capacity_) return;
  chunk_capacity_ = need;
  chunk_counts_ = cl::Buffer();
  chunk_counts_ = checkedBuffer(rt_, CL_MEM_READ_WRITE, need * sizeof(cl_uint), "tiled culling chunk counters");
}

void TileLightCuller::ensureLights(std::uint32_t n) {
  if (n <= light_capacity_) return;
  light_capacity_ = std::size_t(n) + n / 2;
  rects_ = checkedBuffer(rt_, CL_MEM_READ_WRITE, light_capacity_ * 32, "tiled culling light rectangles");
  mask_words_ = checkedBuffer(rt_, CL_MEM_READ_WRITE, light_capacity_ * 4, "tiled culling mask sizes");
  mask_offsets_ = checkedBuffer(rt_, CL_MEM_READ_WRITE, light_capacity_ * 4, "tiled culling mask offsets");
}

std::size_t TileLightCuller::scratchBytes() const {
  return tile_capacity_ * (2 * 16 + 4 * 4 + kLanePlanes * 4) + side_capacity_ * kTileSideBytes +
         light_capacity_ * (32 + 8) + mask_capacity_ * 4 + chunk_capacity_ * 4 + block_capacity_ * 32;
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
    setArgs(bounds_, *depth, cam, tiles_x, tiles_y, tile_bounds_, tile_masks_, tile_boxes_, tile_lanes_);
    // A work-group per tile (GPU shape, or large tiles on a loop-capped device), else a work-item.
    launch1d(q, bounds_, group_bounds_ ? std::size_t(n_tiles) * bounds_local_ : n_tiles, bounds_local_,
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
    if (chunked_) {
      markChunked(q, n, cam, timer);
    } else if (gpu_shape_) {
      writeSides(q, cam, timer);
      setArgs(mark_, rects_, n, words_, cam, tiles_x, tile_bounds_, tile_masks_, tile_boxes_, tile_sides_,
              mask_offsets_, hit_masks_, counts_);
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
  if (chunked_ && n > 0) {  // each chunk's write cursors, from the tile offsets
    setArgs(bases_k_, chunk_counts_, chunks_, n_tiles, offsets_);
    launch1d(q, bases_k_, n_tiles, grid_local_, ev("tile-chunk-bases"));
  }
  return std::uint32_t(total);
}

void TileLightCuller::writeSides(cl::CommandQueue& q, const gpu::CameraParams& cam, ClPassTimer* timer) {
  const cl_uint tiles_x = grid_.tilesX(), tiles_y = grid_.tilesY();
  const std::size_t sides = std::size_t(tiles_x) + tiles_y;
  if (sides > side_capacity_) {
    side_capacity_ = sides;
    tile_sides_ = checkedBuffer(rt_, CL_MEM_READ_WRITE, sides * kTileSideBytes, "tile side planes");
  }
  setArgs(sides_k_, cam, tiles_x, tiles_y, tile_sides_);
  launch1d(q, sides_k_, sides, grid_local_, timer ? timer->next("tile-sides") : nullptr);
}

// CPU shape: the box around each block of kBlockTiles^2 tiles' boxes, which
// lets a light skip the blocks it cannot reach (no blocks without depth bounds).
cl_uint TileLightCuller::writeBlocks(cl::CommandQueue& q, ClPassTimer* timer) {
  const cl_uint tiles_x = grid_.tilesX(), tiles_y = grid_.tilesY();
  const cl_uint blocks_x = (tiles_x + kBlockTiles - 1) / kBlockTiles;
  const std::size_t blocks = std::size_t(blocks_x) * ((tiles_y + kBlockTiles - 1) / kBlockTiles);
  if (mode_ == TileDepthMode::None) return blocks_x;
  if (blocks > block_capacity_) {
    block_capacity_ = blocks;
    blocks_lo_ = checkedBuffer(rt_, CL_MEM_READ_WRITE, blocks * sizeof(cl_float4), "tile block boxes");
    blocks_hi_ = checkedBuffer(rt_, CL_MEM_READ_WRITE, blocks * sizeof(cl_float4), "tile block boxes");
  }
  setArgs(blocks_k_, tile_bounds_, tile_boxes_, tiles_x, tiles_y, blocks_x, blocks_lo_, blocks_hi_);
  launch1d(q, blocks_k_, blocks, grid_local_, timer ? timer->next("tile-blocks") : nullptr);
  return blocks_x;
}

// CPU shape: each chunk counts into its own row; the rows' sums per tile feed
// the scan in count().
void TileLightCuller::markChunked(cl::CommandQueue& q, std::uint32_t n, const gpu::CameraParams& cam,
                                  ClPassTimer* timer) {
  const cl_uint tiles_x = grid_.tilesX(), n_tiles = grid_.count();
  auto ev = [&](const char* name) { return timer ? timer->next(name) : nullptr; };
  writeSides(q, cam, timer);
  const cl_uint blocks_x = writeBlocks(q, timer);
  ensureChunks(n, n_tiles);
  setArgs(mark_, rects_, n, per_chunk_, n_tiles, tiles_x, tile_lanes_, tile_sides_, blocks_lo_, blocks_hi_, blocks_x,
          mask_offsets_, hit_masks_, chunk_counts_);
  launch1d(q, mark_, chunks_, 1, ev("tile-cull"));
  setArgs(totals_k_, chunk_counts_, chunks_, n_tiles, counts_);
  launch1d(q, totals_k_, n_tiles, grid_local_, ev("tile-chunk-totals"));
}

void TileLightCuller::fill(cl::CommandQueue& q, const cl::Buffer& lights, std::uint32_t n,
                           const gpu::CameraParams& cam, cl::Buffer& grid, cl::Buffer& indices, ClPassTimer* timer) {
  (void)lights;  // count() kept everything fill needs (the rectangles and hit masks)
  (void)cam;
  const cl_uint tiles_x = grid_.tilesX(), n_tiles = grid_.count();
  auto ev = [&](const char* name) { return timer ? timer->next(name) : nullptr; };
  if (n > 0) {
    if (chunked_) {
      setArgs(scatter_, rects_, n, per_chunk_, n_tiles, tiles_x, mask_offsets_, hit_masks_, chunk_counts_, indices);
      launch1d(q, scatter_, chunks_, 1, ev("tile-scatter"));
    } else if (gpu_shape_) {
      q.enqueueFillBuffer(cursor_, cl_uint(0), 0, std::size_t(n_tiles) * sizeof(cl_uint));
      setArgs(scatter_, rects_, n, words_, tiles_x, mask_offsets_, hit_masks_, offsets_, cursor_, indices);
      launch1d(q, scatter_, std::size_t(words_) * 32, element_local_, ev("tile-scatter"));
    } else {
      q.enqueueFillBuffer(cursor_, cl_uint(0), 0, std::size_t(n_tiles) * sizeof(cl_uint));
      setArgs(scatter_, rects_, n, tiles_x, mask_offsets_, hit_masks_, offsets_, cursor_, indices);
      launch1d(q, scatter_, n, element_local_, ev("tile-scatter"));
    }
  }
  setArgs(write_grid_, offsets_, counts_, n_tiles, grid);
  launch1d(q, write_grid_, n_tiles, grid_local_, ev("tile-grid"));
}

}  // namespace ml
