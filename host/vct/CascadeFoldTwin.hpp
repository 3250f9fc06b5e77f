#pragma once
// The C++ twin of kernels/vct/vct_cascade_fold.cl (CascadeFold.hpp): the
// coarser level's level-0 voxels in foldBox(fine, coarse) take the opacity
// of the finer level's mip level 1 voxels at the same lattice cells, at
// their own colour (the mip's where they are empty). `fine` holds every
// level of the finer radiance volume, `coarse` at least the coarser level 0;
// the levels must be foldable().
#include <vector>

#include "host/shared/gpu_types.h"
#include "host/shared/voxel_types.h"

namespace ml::vct {

void cascadeFoldTwin(const std::vector<gpu::ml_float4>& fine, const gpu::VoxelGridParams& fine_grid,
                     std::vector<gpu::ml_float4>& coarse, const gpu::VoxelGridParams& coarse_grid);

}  // namespace ml::vct
