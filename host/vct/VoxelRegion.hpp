#pragma once
// A part of a voxel grid's window, as boxes of window coordinates (voxel
// indices 0..edge-1 per axis, voxel_types.h; `hi` exclusive): the slabs a
// scrolled cascade level must voxelize and inject again
// (host/vct/VoxelCascade.hpp). Boxes may overlap; an empty region is the
// whole grid. At most kMaxRegionBoxes boxes (one slab per axis, and the box
// a finer cascade level's window left: VctPipeline).
#include <array>
#include <cstddef>
#include <vector>

#include "host/shared/vct_bindings.h"

namespace ml::vct {

inline constexpr std::size_t kMaxRegionBoxes = ML_VOXEL_REGION_BOXES;

struct VoxelBox {
  std::array<unsigned, 3> lo{}, hi{};
  std::size_t voxels() const {
    std::size_t n = 1;
    for (int a = 0; a < 3; ++a) n *= hi[a] > lo[a] ? hi[a] - lo[a] : 0;
    return n;
  }
  bool contains(unsigned x, unsigned y, unsigned z) const {
    return x >= lo[0] && y >= lo[1] && z >= lo[2] && x < hi[0] && y < hi[1] && z < hi[2];
  }
};

using VoxelRegion = std::vector<VoxelBox>;

// Voxels in the union of the region's boxes of a grid of `edge` (edge^3 when empty).
std::size_t regionVoxels(const VoxelRegion& r, unsigned edge);

// std::invalid_argument for more than kMaxRegionBoxes boxes or a box outside 0..edge.
void checkRegion(const VoxelRegion& r, unsigned edge);

}  // namespace ml::vct
