#include "host/vct/VoxelRegion.hpp"

#include <stdexcept>
#include <string>

namespace ml::vct {

// By counting: regions are at most three slabs of a grid of at most 512^3,
// and this runs in tests and reports, not per frame on the device.
std::size_t regionVoxels(const VoxelRegion& r, unsigned edge) {
  if (r.empty()) return std::size_t(edge) * edge * edge;
  std::size_t n = 0;
  for (unsigned z = 0; z < edge; ++z)
    for (unsigned y = 0; y < edge; ++y)
      for (unsigned x = 0; x < edge; ++x)
        for (const VoxelBox& b : r)
          if (b.contains(x, y, z)) {
            ++n;
            break;
          }
  return n;
}

void checkRegion(const VoxelRegion& r, unsigned edge) {
  if (r.size() > kMaxRegionBoxes)
    throw std::invalid_argument("voxel region: " + std::to_string(r.size()) + " boxes, at most " +
                                std::to_string(kMaxRegionBoxes));
  for (const VoxelBox& b : r)
    for (int a = 0; a < 3; ++a)
      if (b.lo[a] > b.hi[a] || b.hi[a] > edge)
        throw std::invalid_argument("voxel region: a box outside the grid of edge " + std::to_string(edge));
}

}  // namespace ml::vct
