#pragma once
// Resolve + light injection on the device (kernels/vct/vct_inject.cl): level 0 of
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
// A toroidal grid (VoxelGridParams::wrap, a cascade level) is read and
// written where voxel_shift() puts its voxels; a non-empty `region` writes
// only the voxels in its boxes (a scrolled level's new slabs) and leaves the
// rest of level 0 as it was. Shadows need an unscrolled grid.
// shadows = true (--vct-shadows voxel) builds the kernels with VCT_SHADOWS:
// each light's term times its visibility through the filled level-0 voxels
// of `accum` (InjectTwin's voxelVisibility()); false compiles none of it.
// With skip_empty (the default) the march skips empty space through the
// empty-space distance volume of `accum` (VoxelOccupancy): the caller's, built from
// the same accumulation buffer, or, when none is given, one built here on
// every call (timed as "vct-occupancy"). Its decisions equal the plain march
// (skip_empty = false: every sample loads its voxel; the bench's peer).
#include <CL/opencl.hpp>

#include <cstddef>
#include <vector>

#include "host/cl/ClPassTimer.hpp"
#include "host/compute/ComputeEnv.hpp"
#include "host/shared/voxel_types.h"
#include "host/vct/HashedListsCl.hpp"
#include "host/vct/VoxelOccupancy.hpp"
#include "host/vct/VoxelRegion.hpp"

namespace ml::vct {

class VoxelInjector {
 public:
  explicit VoxelInjector(const compute::ComputeEnv& env, const compute::Options& options = {}, bool shadows = false,
                         bool skip_empty = true);

  bool shadows() const { return shadows_; }

  void brute(cl::CommandQueue& q, const gpu::VoxelGridParams& g, const cl::Buffer& accum, const cl::Buffer& lights,
             std::size_t light_count, cl::Buffer& radiance, ClPassTimer* timer = nullptr,
             const VoxelOccupancy* occupancy = nullptr, const VoxelRegion& region = {});
  void hashed(cl::CommandQueue& q, const gpu::VoxelGridParams& g, const cl::Buffer& accum, const cl::Buffer& lights,
              std::size_t light_count, const HashedListsCl& lists, cl::Buffer& radiance,
              ClPassTimer* timer = nullptr, const VoxelOccupancy* occupancy = nullptr,
              const VoxelRegion& region = {});

  // Tests: the shadow march alone (shadows only, else std::logic_error), per
  // query from a surfel at pn[2q] with unit normal pn[2q + 1] (xyz) to the
  // light position lp[q] (xyz), on the grid `g` of `accum` (occupancy built
  // here): whether the light is seen, and how many samples the march looked at.
  struct MarchResult {
    bool visible;
    unsigned tested;
  };
  std::vector<MarchResult> march(cl::CommandQueue& q, const gpu::VoxelGridParams& g, const cl::Buffer& accum,
                                 const std::vector<gpu::ml_float4>& pn, const std::vector<gpu::ml_float4>& lp);

  const compute::Tuning& tuning() const { return tuning_; }

 private:
  // Checks the buffers, builds the kernels, sets the kArgLights + 1 arguments
  // both kernels share; returns the launch's global size, local size in `local`.
  std::size_t prepare(cl::Kernel& k, cl::CommandQueue& q, const gpu::VoxelGridParams& g, const cl::Buffer& accum,
                      const cl::Buffer& lights, std::size_t light_count, cl::Buffer& radiance, std::size_t& local,
                      ClPassTimer* timer, const VoxelOccupancy* occupancy, const VoxelRegion& region);
  static constexpr cl_uint kArgLights = 10;  // the lights; the kernels' own arguments follow
  void build();
  // The occupancy buffer the kernels read: the caller's, else own_ built
  // from `accum` now; `accum` itself (unread) when the march does not skip.
  const cl::Buffer& occupancyFor(cl::CommandQueue& q, const gpu::VoxelGridParams& g, const cl::Buffer& accum,
                                 ClPassTimer* timer, const VoxelOccupancy* occupancy);

  compute::ComputeEnv env_;
  compute::Tuning tuning_;
  bool shadows_, skip_;
  cl::Kernel brute_, hashed_, probe_;
  VoxelOccupancy own_;
  cl::Buffer boxes_;  // the region's boxes, 2 uint4 each (kMaxRegionBoxes)
};

}  // namespace ml::vct
