#include "host/vct/CascadeFoldTwin.hpp"

#include <stdexcept>

#include "host/vct/CascadeFold.hpp"

namespace ml::vct {
namespace {

// The kernel's stored_at(): where lattice index j lives in a level of `edge` whose window starts at `corner`.
std::size_t storedAt(long long j, long long corner, bool wrap, unsigned edge) {
  return wrap ? static_cast<std::size_t>(j & (edge - 1)) : static_cast<std::size_t>(j - corner);
}

// The kernel's fold_voxel(), same float operations.
gpu::ml_float4 foldVoxel(const gpu::ml_float4& own, const gpu::ml_float4& fine) {
  float c[3] = {0, 0, 0};
  if (own.w > 0.0f) {
    c[0] = own.x / own.w, c[1] = own.y / own.w, c[2] = own.z / own.w;
  } else if (fine.w > 0.0f) {
    c[0] = fine.x / fine.w, c[1] = fine.y / fine.w, c[2] = fine.z / fine.w;
  }
  return {c[0] * fine.w, c[1] * fine.w, c[2] * fine.w, fine.w};
}

}  // namespace

void cascadeFoldTwin(const std::vector<gpu::ml_float4>& fine, const gpu::VoxelGridParams& fine_grid,
                     std::vector<gpu::ml_float4>& coarse, const gpu::VoxelGridParams& coarse_grid) {
  if (!foldable(fine_grid, coarse_grid)) throw std::invalid_argument("cascadeFoldTwin: the levels do not nest");
  const VoxelBox box = foldBox(fine_grid, coarse_grid);
  const LatticeCorner f = latticeCorner(fine_grid), c = latticeCorner(coarse_grid);
  const long long fh[3] = {f.x / 2, f.y / 2, f.z / 2}, cc[3] = {c.x, c.y, c.z};
  const unsigned fe = fine_grid.edge / 2, ce = coarse_grid.edge;
  const std::size_t base = std::size_t(fine_grid.edge) * fine_grid.edge * fine_grid.edge;
  for (unsigned z = box.lo[2]; z < box.hi[2]; ++z)
    for (unsigned y = box.lo[1]; y < box.hi[1]; ++y)
      for (unsigned x = box.lo[0]; x < box.hi[0]; ++x) {
        const unsigned w[3] = {x, y, z};
        std::size_t fi[3], ci[3];
        for (int a = 0; a < 3; ++a) {
          const long long j = cc[a] + w[a];
          fi[a] = storedAt(j, fh[a], fine_grid.wrap != 0, fe);
          ci[a] = storedAt(j, cc[a], coarse_grid.wrap != 0, ce);
        }
        gpu::ml_float4& own = coarse.at(ci[0] + ce * (ci[1] + ce * ci[2]));
        own = foldVoxel(own, fine.at(base + fi[0] + fe * (fi[1] + fe * fi[2])));
      }
}

}  // namespace ml::vct
