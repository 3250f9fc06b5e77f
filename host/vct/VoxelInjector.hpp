#pragma once
// Resolve + light injection on the device (kernels/vct_inject.cl): level 0 of
// the radiance/opacity volume from the accumulation buffer and the lights.
//  - brute(): every light for every filled voxel (the reference, and the
//    bench's peer).
//  - hashed(): the lights of the hashed structure's list at each voxel
//    centre (HashedListsCl, uploaded by the caller from the structure built
//    over the same light array). Equal to brute() up to summation order.
// Writes the first edge^3 float4 of `radiance` (level 0); both kernel shapes
// (compute::Shape); timed as "vct-inject" when a timer is given. The C++
// twin is InjectTwin.hpp. Buffers are checked against the grid and light
// count (std::invalid_argument). Not thread-safe.
// shadows = true (--vct-shadows voxel) builds the kernels with VCT_SHADOWS:
// each light's term times its visibility through the filled level-0 voxels
// of `accum` (InjectTwin's voxelVisibility()); false compiles none of it.
#include <CL/opencl.hpp>

#include <cstddef>

#include "host/cl/ClPassTimer.hpp"
#include "host/compute/ComputeEnv.hpp"
#include "host/shared/voxel_types.h"
#include "host/vct/HashedListsCl.hpp"

namespace ml::vct {

class VoxelInjector {
 public:
  explicit VoxelInjector(const compute::ComputeEnv& env, const compute::Options& options = {}, bool shadows = false);

  bool shadows() const { return shadows_; }

  void brute(cl::CommandQueue& q, const gpu::VoxelGridParams& g, const cl::Buffer& accum, const cl::Buffer& lights,
             std::size_t light_count, cl::Buffer& radiance, ClPassTimer* timer = nullptr);
  void hashed(cl::CommandQueue& q, const gpu::VoxelGridParams& g, const cl::Buffer& accum, const cl::Buffer& lights,
              std::size_t light_count, const HashedListsCl& lists, cl::Buffer& radiance,
              ClPassTimer* timer = nullptr);

  const compute::Tuning& tuning() const { return tuning_; }

 private:
  // Checks the buffers, builds the kernels, sets the 6 arguments both
  // kernels share; returns the launch's global size, local size in `local`.
  std::size_t prepare(cl::Kernel& k, const gpu::VoxelGridParams& g, const cl::Buffer& accum,
                      const cl::Buffer& lights, std::size_t light_count, cl::Buffer& radiance, std::size_t& local);

  compute::ComputeEnv env_;
  compute::Tuning tuning_;
  bool shadows_;
  cl::Kernel brute_, hashed_;
};

}  // namespace ml::vct
