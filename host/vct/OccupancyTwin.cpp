#include "host/vct/OccupancyTwin.hpp"

#include <algorithm>
#include <stdexcept>

#include "host/shared/voxel_occupancy.h"

namespace ml::vct {

namespace {

bool bit(const std::vector<std::uint32_t>& w, std::size_t offset, std::size_t c) {
  return (w[offset + c / 32] >> (c % 32)) & 1u;
}

void set(std::vector<std::uint32_t>& w, std::size_t offset, std::size_t c) { w[offset + c / 32] |= 1u << (c % 32); }

// Level l + 1 from level l: a bit per 4^3 block with any bit set.
void reduceLevel(std::vector<std::uint32_t>& w, unsigned edge, unsigned l) {
  const unsigned se = gpu::occupancy_level_edge(edge, l), de = gpu::occupancy_level_edge(edge, l + 1);
  const std::size_t so = gpu::occupancy_level_offset(edge, l), dof = gpu::occupancy_level_offset(edge, l + 1);
  const unsigned s = 1u << ML_OCC_BLOCK_LOG2;
  for (unsigned z = 0; z < se; ++z)
    for (unsigned y = 0; y < se; ++y)
      for (unsigned x = 0; x < se; ++x)
        if (bit(w, so, x + std::size_t(se) * (y + std::size_t(se) * z)))
          set(w, dof, x / s + std::size_t(de) * (y / s + std::size_t(de) * (z / s)));
}

}  // namespace

std::vector<std::uint32_t> occupancyTwin(const std::vector<gpu::VoxelAccum>& accum, unsigned edge) {
  if (edge == 0 || edge > ML_VOXEL_MAX_EDGE) throw std::invalid_argument("occupancyTwin: edge out of range");
  const std::size_t n = std::size_t(edge) * edge * edge;
  if (accum.size() < n) throw std::invalid_argument("occupancyTwin: accumulation buffer smaller than the grid");
  std::vector<std::uint32_t> w(gpu::occupancy_level_offset(edge, ML_OCC_LEVELS), 0u);
  for (std::size_t i = 0; i < n; ++i)
    if (accum[i].albedo_count[3] != 0) set(w, 0, i);
  for (unsigned l = 0; l + 1 < ML_OCC_LEVELS; ++l) reduceLevel(w, edge, l);
  return w;
}

}  // namespace ml::vct
