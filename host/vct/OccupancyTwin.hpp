#pragma once
// The C++ twin of kernels/vct_occupancy.cl: the occupancy hierarchy
// (host/shared/voxel_occupancy.h) of a level-0 accumulation grid of `edge`
// voxels per axis (any edge 1 .. ML_VOXEL_MAX_EDGE), all ML_OCC_LEVELS levels
// in one word vector, equal to the kernels' buffer bit for bit.
#include <cstdint>
#include <vector>

#include "host/shared/voxel_types.h"

namespace ml::vct {

std::vector<std::uint32_t> occupancyTwin(const std::vector<gpu::VoxelAccum>& accum, unsigned edge);

}  // namespace ml::vct
