#pragma once
// The C++ twin of kernels/vct/vct_occupancy.cl: the empty-space distance volume
// (host/shared/voxel_occupancy.h) of a level-0 accumulation grid of `edge`
// voxels per axis (any edge 1 .. ML_VOXEL_MAX_EDGE), equal to the kernels'
// buffer byte for byte. Written from the passes' definitions (every pair of a
// line, no early stop), not from the kernels' loops.
#include <cstdint>
#include <vector>

#include "host/shared/voxel_types.h"

namespace ml::vct {

std::vector<std::uint8_t> occupancyTwin(const std::vector<gpu::VoxelAccum>& accum, unsigned edge);

}  // namespace ml::vct
