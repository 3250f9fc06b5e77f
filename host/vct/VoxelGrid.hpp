#pragma once
// Settings of the voxel cone tracing grid and what they cost.
// Contract:
//  - checkVoxelGrid() accepts voxels = 2^k in 1..ML_VOXEL_MAX_EDGE and levels
//    in 1..log2(voxels) + 1, else throws UserError with one line naming the
//    flag (--voxels, --levels), which the CLI turns into exit status 2.
//  - voxelBytes() is the device memory of one configuration: the level-0
//    accumulation buffer, the radiance/opacity volume of all levels and, when
//    anisotropic, the 6-direction volume of levels >= 1 (voxel_types.h).
//  - fitVoxelGrid() returns the cube of `edge` voxels centred on an AABB,
//    `voxels` - 2 voxels spanning the AABB's longest side, leaving one voxel
//    of margin on each end so that surfaces on the bounds fall inside a voxel
//    rather than on the grid's face (edges 1 and 2: the side spans 1 voxel).
#include <cstddef>

#include "host/scene/Scene.hpp"
#include "host/shared/voxel_types.h"

namespace ml::vct {

struct VoxelGridSettings {
  unsigned voxels = 64;  // level-0 voxels per axis
  unsigned levels = 5;   // autoLevels(64), --levels auto
  bool anisotropic = true;  // --anisotropic (on by default)
};

void checkVoxelGrid(const VoxelGridSettings& s);  // UserError naming --voxels / --levels

// log2 of a power of two.
unsigned log2Exact(unsigned pow2);

// --levels auto: log2(voxels) - 1 (at least 1), so the coarsest level is four
// voxels across, the same world size at every --voxels: a finer grid refines
// every level. A fixed count made the coarsest level shrink with the voxels,
// and wide cones read it too sharp (Cornell box, anisotropic, 9 cones,
// relative RMSE at 128^3: 4 levels 0.161, 5 0.151, auto (6) 0.141; 64^3: 4
// levels 0.163, auto (5) 0.148).
unsigned autoLevels(unsigned voxels);

// Voxels of levels 0 .. levels - 1 together, and of levels 1 .. levels - 1.
std::size_t voxelsAllLevels(unsigned edge, unsigned levels);
std::size_t voxelsCoarseLevels(unsigned edge, unsigned levels);

std::size_t accumBytes(const VoxelGridSettings& s);
std::size_t radianceBytes(const VoxelGridSettings& s);
std::size_t anisotropicBytes(const VoxelGridSettings& s);  // 0 unless s.anisotropic
std::size_t voxelBytes(const VoxelGridSettings& s);        // the three above

// Checks `s` first. An empty AABB (no geometry) gets a unit cube at the origin.
gpu::VoxelGridParams fitVoxelGrid(const Aabb& bounds, const VoxelGridSettings& s);

}  // namespace ml::vct
