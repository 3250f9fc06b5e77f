#pragma once
// Voxel mip propagation on the device (kernels/vct/vct_mips.cl): levels 1 ..
// levels - 1 of the radiance/opacity volume from its level 0 (isotropic:
// child pairs composited along each axis in the brighter of the two orders,
// the most opaque axis kept) and of
// the 6-direction volume (anisotropic, Crassin 2011; its level 1 from
// isotropic level 0). One launch per kTreeDepth levels, each top parent's
// subtree in one work-item (CPU shape) or work-group (GPU shape), launches in
// level order on the queue. Both kernel shapes (compute::Shape,
// ComputeEnv.hpp); the C++ twin is VoxelMipsReference.hpp, equal bit for bit
// (the kernels do not fuse multiply-adds). Buffers hold the layouts of
// host/shared/voxel_types.h and are checked against the grid's size
// (std::invalid_argument). Not thread-safe.
#include <CL/opencl.hpp>

#include "host/cl/ClPassTimer.hpp"
#include "host/compute/ComputeEnv.hpp"
#include "host/shared/voxel_types.h"

namespace ml::vct {

class VoxelMips {
 public:
  explicit VoxelMips(const compute::ComputeEnv& env, const compute::Options& options = {});

  // Timed as "vct-mips" when a timer is given.
  void isotropic(cl::CommandQueue& q, const gpu::VoxelGridParams& g, cl::Buffer& radiance,
                 ClPassTimer* timer = nullptr);
  void anisotropic(cl::CommandQueue& q, const gpu::VoxelGridParams& g, const cl::Buffer& radiance,
                   cl::Buffer& aniso, ClPassTimer* timer = nullptr);

  const compute::Tuning& tuning() const { return tuning_; }

 private:
  void build();
  // Levels per launch: subtrees of 8^3 level-0 voxels under each top parent
  // fit in a core's L1/L2 while it walks them.
  static constexpr unsigned kTreeDepth = 3;
  void launchTrees(cl::CommandQueue& q, cl::Kernel& k, cl_uint first_arg, const gpu::VoxelGridParams& g,
                   ClPassTimer* timer);

  compute::ComputeEnv env_;
  compute::Tuning tuning_;
  cl::Kernel iso_, aniso_;
};

}  // namespace ml::vct
