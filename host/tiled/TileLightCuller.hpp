#pragma once
// GPU-side tile light culling (kernels/tiled_light_culling.cl), independent of
// GL so it can be tested and benchmarked on plain CL buffers:
//
//   TileLightCuller culler(rt, 16, TileDepthMode::MinMax);
//   uint32_t total = culler.count(q, lights, n, cam, &depth);   // bounds, count, scan
//   ... make `indices` hold >= total uints ...
//   culler.fill(q, lights, n, cam, grid, indices);              // grid: LightRange per tile
//
// count() blocks twice (for the size of the per-light hit masks and for the
// list total): everything is sized from those, so nothing can overflow or be
// truncated. The order inside a tile's
// list is unspecified (atomics).
#include <CL/opencl.hpp>

#include <cstdint>

#include "host/cl/ClPassTimer.hpp"
#include "host/cl/ClRuntime.hpp"
#include "host/compute/Scan.hpp"
#include "host/tiled/TileGeometry.hpp"

namespace ml {

class TileLightCuller {
 public:
  TileLightCuller(ClRuntime& rt, unsigned tile_size, TileDepthMode mode);

  // depth: window-space floats (cam.width x cam.height, row 0 bottom); may be
  // null only when the mode is None.
  std::uint32_t count(cl::CommandQueue& q, const cl::Buffer& lights, std::uint32_t n, const gpu::CameraParams& cam,
                      const cl::Buffer* depth, ClPassTimer* timer = nullptr);
  // Same lights and camera as the preceding count().
  void fill(cl::CommandQueue& q, const cl::Buffer& lights, std::uint32_t n, const gpu::CameraParams& cam,
            cl::Buffer& grid, cl::Buffer& indices, ClPassTimer* timer = nullptr);

  const TileGrid& tileGrid() const { return grid_; }
  TileDepthMode mode() const { return mode_; }
  std::size_t scratchBytes() const;

 private:
  void ensureTiles(const gpu::CameraParams& cam);
  ClRuntime& rt_;
  TileDepthMode mode_;
  TileGrid grid_;
  bool gpu_shape_;
  cl::Program program_;
  cl::Kernel bounds_, rects_k_, mark_, scatter_, write_grid_;
  cl::Buffer tile_bounds_, tile_masks_, counts_, offsets_, cursor_;
  cl::Buffer rects_, mask_words_, mask_offsets_, hit_masks_;
  std::size_t tile_capacity_ = 0, light_capacity_ = 0, mask_capacity_ = 0;
  compute::Scanner scan_;
};

}  // namespace ml
