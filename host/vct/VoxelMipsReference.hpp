#pragma once
// The C++ twins of kernels/vct/vct_mips.cl: the same filters with the same float
// operations in the same order, one voxel at a time (tests compare the
// kernels with these bit for bit; see VoxelMips.hpp for the filters).
//  - mipIsotropicTwin(): fills levels 1 .. levels - 1 of `radiance` (all
//    levels, voxel_level_offset() layout) from its level 0.
//  - mipAnisotropicTwin(): fills `aniso` (voxel_aniso_index() layout, resized
//    to hold levels 1 .. levels - 1) from level 0 of `radiance`.
#include <vector>

#include "host/shared/voxel_types.h"

namespace ml::vct {

void mipIsotropicTwin(std::vector<gpu::ml_float4>& radiance, unsigned edge, unsigned levels);
void mipAnisotropicTwin(const std::vector<gpu::ml_float4>& radiance, std::vector<gpu::ml_float4>& aniso,
                        unsigned edge, unsigned levels);

}  // namespace ml::vct
