#pragma once
// GPU-side tile light culling (kernels/tiled/tiled_light_culling.cl), independent of
// GL so it can be tested and benchmarked on plain CL buffers:
//
//   TileLightCuller culler(rt, 16, TileDepthMode::MinMax);
//   uint32_t total = culler.count(q, lights, n, cam, &depth);   // bounds, count, scan
//   ... make `indices` hold >= total uints ...
//   culler.fill(q, lights, n, cam, grid, indices);              // grid: LightRange per tile
//
// count() blocks twice (for the size of the per-light hit masks and for the
// list total): everything is sized from those, so nothing can overflow or be
// truncated. Totals that could pass 2^32 (lights x tiles, e.g. 1M lights at
// 4K) are summed again in 64 bits; a list or mask that 32-bit offsets or the
// device's largest allocation cannot hold is a UserError, never a wrap; so is,
// in the CPU shape on a device that ends a work-item's loops early (llvmpipe:
// 65,535 iterations, tests/driver/driver_loop_cap_test.cpp), a screen where one
// light's rectangle could pass that cap (its chunks are sized under it). The
// order inside a tile's list is unspecified (atomics).
//
// Kernel shape (KernelShape, --kernel-shape): CpuChunked gives each work-item
// a chunk of lights whose rectangles it walks, counting into its own row of
// per-tile counters (no atomics; lists come out in ascending light order), and
// a tile's pixels per work-item for the depth bounds; GpuWorkGroup gives each
// (light, tile) pair a work-item (an atomic count per list entry, order
// unspecified) and each tile's depth a work-group. Both give the same grid and
// the same lists up to order; Auto picks by device type, but the GPU shape
// on a device that caps loops (the CPU shape's refusal above). Both hoist the
// per-tile culling math (side planes, depth box) out of the per-pair loop.
//
// TileCullAlgorithm::PairAtomics is the culler before that rework (per-pair
// math, an atomic per list entry in both shapes), kept for the benchmark's
// same-run comparison; the lists are the same.
#include <CL/opencl.hpp>

#include <cstdint>

#include "host/cl/ClPassTimer.hpp"
#include "host/cl/ClRuntime.hpp"
#include "host/cl/KernelLimits.hpp"
#include "host/compute/Scan.hpp"
#include "host/tiled/TileGeometry.hpp"

namespace ml {

enum class TileCullAlgorithm { ChunkCounts, PairAtomics };

class TileLightCuller {
 public:
  TileLightCuller(ClRuntime& rt, unsigned tile_size, TileDepthMode mode, KernelShape shape = KernelShape::Auto,
                  TileCullAlgorithm algorithm = TileCullAlgorithm::ChunkCounts);

  // depth: window-space floats (cam.width x cam.height, row 0 bottom); may be
  // null only when the mode is None.
  std::uint32_t count(cl::CommandQueue& q, const cl::Buffer& lights, std::uint32_t n, const gpu::CameraParams& cam,
                      const cl::Buffer* depth, ClPassTimer* timer = nullptr);
  // Same lights and camera as the preceding count().
  void fill(cl::CommandQueue& q, const cl::Buffer& lights, std::uint32_t n, const gpu::CameraParams& cam,
            cl::Buffer& grid, cl::Buffer& indices, ClPassTimer* timer = nullptr);

  const TileGrid& tileGrid() const { return grid_; }
  // Hit-mask words of the last count(): a word per 32 tiles of each light's
  // rectangle (so the rectangles' sizes, as lightTileRect computes them).
  std::uint32_t maskWords() const { return words_; }
  TileDepthMode mode() const { return mode_; }
  KernelShape shape() const { return shape_; }  // resolved, never Auto
  std::size_t scratchBytes() const;

 private:
  void ensureTiles(const gpu::CameraParams& cam);
  void ensureLights(std::uint32_t n);
  void ensureChunks(std::uint32_t n, std::size_t n_tiles);
  void writeSides(cl::CommandQueue& q, const gpu::CameraParams& cam, ClPassTimer* timer);
  cl_uint writeBlocks(cl::CommandQueue& q, ClPassTimer* timer);
  void markChunked(cl::CommandQueue& q, std::uint32_t n, const gpu::CameraParams& cam, ClPassTimer* timer);
  std::uint64_t exactTotal(cl::CommandQueue& q, const cl::Buffer& values, std::size_t n, std::uint32_t wrapped,
                           std::uint64_t per_item_max) const;
  ClRuntime& rt_;
  TileDepthMode mode_;
  TileGrid grid_;
  KernelShape shape_;
  bool gpu_shape_;
  bool chunked_;  // CPU shape of ChunkCounts: per-chunk counters instead of atomics
  bool group_bounds_ = false;  // depth bounds by tile_depth_bounds_wg (a work-group per tile)
  std::size_t bounds_local_ = 1, element_local_ = 1, mark_local_ = 32, rects_local_ = 1, grid_local_ = 1;
  cl::Program program_;
  cl::Kernel bounds_, rects_k_, mark_, scatter_, write_grid_, sides_k_, totals_k_, bases_k_, blocks_k_;
  cl::Buffer tile_bounds_, tile_masks_, tile_boxes_, tile_lanes_, tile_sides_, counts_, offsets_, cursor_, chunk_counts_;
  cl::Buffer rects_, mask_words_, mask_offsets_, hit_masks_, blocks_lo_, blocks_hi_;
  std::size_t tile_capacity_ = 0, light_capacity_ = 0, mask_capacity_ = 0;
  std::uint32_t words_ = 0;  // hit-mask words of the last count()
  std::size_t side_capacity_ = 0, chunk_capacity_ = 0, block_capacity_ = 0;
  std::uint32_t chunks_ = 0, per_chunk_ = 0;  // CPU shape: work-items and lights per work-item of the last count()
  compute::Scanner scan_;
};

}  // namespace ml
