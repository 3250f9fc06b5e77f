#pragma once
// Voxel mip propagation on the device (kernels/vct_mips.cl): levels 1 ..
// levels - 1 of the radiance/opacity volume from its level 0 (isotropic,
// 002's alpha-weighted box filter) and of the 6-direction volume
// (anisotropic, Crassin 2011; its level 1 from isotropic level 0). One
// launch per level, in level order on the queue (each reads the previous).
// Both kernel shapes (compute::Shape, ComputeEnv.hpp); the C++ twin is
// VoxelMipsReference.hpp, equal bit for bit (the kernels do not fuse
// multiply-adds). Buffers hold the layouts of host/shared/voxel_types.h and
// are checked against the grid's size (std::invalid_argument). Not
// thread-safe.
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
  // Global and local size, and the CPU chunk, for n parents.
  void shapeFor(std::size_t n, std::size_t& global, std::size_t& local, std::size_t& chunk) const;

  compute::ComputeEnv env_;
  compute::Tuning tuning_;
  cl::Kernel iso_, aniso_;
};

}  // namespace ml::vct
