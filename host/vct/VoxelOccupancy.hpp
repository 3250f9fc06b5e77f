#pragma once
// The empty-space distance volume of a level-0 accumulation grid on the
// device (kernels/vct/vct_occupancy.cl; layout host/shared/voxel_occupancy.h): a
// byte per voxel, its Chebyshev distance to the nearest filled voxel (clamped),
// which the voxel-shadow march of VoxelInjector reads to skip empty space. Built once per voxelization (the
// geometry, not the lights, decides it), timed as "vct-occupancy". Both
// kernel shapes (compute::Shape); the C++ twin is OccupancyTwin.hpp, equal bit
// for bit. Any edge 1 .. ML_VOXEL_MAX_EDGE (std::invalid_argument otherwise,
// or for an accumulation buffer smaller than edge^3). Not thread-safe.
#include <CL/opencl.hpp>

#include <cstddef>

#include "host/cl/ClPassTimer.hpp"
#include "host/compute/ComputeEnv.hpp"

namespace ml::vct {

class VoxelOccupancy {
 public:
  explicit VoxelOccupancy(const compute::ComputeEnv& env, const compute::Options& options = {});

  void build(cl::CommandQueue& q, unsigned edge, const cl::Buffer& accum, ClPassTimer* timer = nullptr);

  // The bytes of the last build, of the grid edge(); 0 before the first.
  const cl::Buffer& buffer() const { return buffer_; }
  unsigned edge() const { return edge_; }
  const compute::Tuning& tuning() const { return tuning_; }

 private:
  // Launches `k` over `lines` lines of a grid of `edge` (arguments but the last two set).
  void launchLines(cl::CommandQueue& q, cl::Kernel& k, cl_uint lines_arg, std::size_t lines, unsigned edge,
                   ClPassTimer* timer);

  compute::ComputeEnv env_;
  compute::Tuning tuning_;
  cl::Kernel rows_, lines_;
  cl::Buffer buffer_, tmp_;   // the result; the y pass's output
  std::size_t capacity_ = 0;  // bytes of each
  unsigned edge_ = 0;
};

}  // namespace ml::vct
