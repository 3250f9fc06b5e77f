#include "host/vct/VoxelRegion.hpp"

#include <algorithm>
#include <stdexcept>
#include <string>

namespace ml::vct {

namespace {

VoxelBox intersect(const VoxelBox& a, const VoxelBox& b) {
  VoxelBox r;
  for (int k = 0; k < 3; ++k) {
    r.lo[k] = std::max(a.lo[k], b.lo[k]);
    r.hi[k] = std::min(a.hi[k], b.hi[k]);
  }
  return r;
}

}  // namespace

// Inclusion-exclusion over the at most kMaxRegionBoxes boxes (their
// intersections are boxes too): every subset, signed by its size.
std::size_t regionVoxels(const VoxelRegion& r, unsigned edge) {
  if (r.empty()) return std::size_t(edge) * edge * edge;
  checkRegion(r, edge);
  long long n = 0;
  const unsigned subsets = 1u << r.size();
  for (unsigned m = 1; m < subsets; ++m) {
    VoxelBox b{{0, 0, 0}, {edge, edge, edge}};
    int count = 0;
    for (std::size_t i = 0; i < r.size(); ++i)
      if (m & (1u << i)) {
        b = intersect(b, r[i]);
        ++count;
      }
    n += (count % 2 ? 1 : -1) * static_cast<long long>(b.voxels());
  }
  return static_cast<std::size_t>(n);
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
