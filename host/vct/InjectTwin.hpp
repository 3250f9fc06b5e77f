#pragma once
// The C++ twin of kernels/vct/vct_inject.cl's inject_brute: resolve every
// level-0 voxel of the accumulation buffer and light it with every light,
// with the kernel's float operations in its order (resolveVoxel(), then
// shading_model.h per light in index order). It is also what inject_hashed
// must equal: the hashed lists hold every light that reaches a voxel centre,
// so the two differ only in summation order (tests: relative tolerance).
// shadows = true is the kernel built with VCT_SHADOWS (--vct-shadows voxel):
// each light's term times voxelVisibility().
#include <vector>

#include "host/shared/gpu_types.h"
#include "host/shared/voxel_types.h"

namespace ml::vct {

struct Surfel {
  float albedo[3];
  float n[3];  // unit, or zero when the voxel's normals cancel
  float p[3];  // voxel centre
};

// False (and `s` untouched) for an empty voxel.
bool resolveVoxel(const gpu::VoxelAccum& a, unsigned i, const gpu::VoxelGridParams& g, Surfel& s);

// 1 when no filled level-0 voxel lies between `s` (one voxel off its surface
// along its normal) and the light position `lp`, else 0: the kernel's
// voxel_visibility(), same float operations (kernels/vct/vct_inject.cl), as its
// plain march: every sample in turn, which the kernel's skipping march must
// equal. `tested` (if given) gets the number of samples it looked at.
float voxelVisibility(const std::vector<gpu::VoxelAccum>& accum, const gpu::VoxelGridParams& g, const Surfel& s,
                      const float lp[3], unsigned* tested = nullptr);

// One float4 per voxel: (albedo * ML_SHADE_DIRECT * sum, 1), or zero.
std::vector<gpu::ml_float4> injectTwin(const std::vector<gpu::VoxelAccum>& accum, const gpu::VoxelGridParams& g,
                                       const std::vector<gpu::PointLight>& lights, bool shadows = false);

}  // namespace ml::vct
