#include "host/vct/OccupancyTwin.hpp"

#include <algorithm>
#include <stdexcept>

#include "host/shared/voxel_occupancy.h"

namespace ml::vct {

namespace {

// f'(i) = min over j of max(|i - j|, f(j)) along every line of `stride`.
std::vector<std::uint8_t> linePass(const std::vector<std::uint8_t>& in, unsigned edge, std::size_t stride) {
  std::vector<std::uint8_t> out(in.size());
  const std::size_t lines = std::size_t(edge) * edge;
  for (std::size_t l = 0; l < lines; ++l) {
    const std::size_t base = l % stride + l / stride * stride * edge;
    for (unsigned i = 0; i < edge; ++i) {
      unsigned best = in[base + i * stride];
      for (unsigned j = 0; j < edge; ++j)
        best = std::min(best, std::max(unsigned(i > j ? i - j : j - i), unsigned(in[base + j * stride])));
      out[base + i * stride] = std::uint8_t(best);
    }
  }
  return out;
}

}  // namespace

std::vector<std::uint8_t> occupancyTwin(const std::vector<gpu::VoxelAccum>& accum, unsigned edge) {
  if (edge == 0 || edge > ML_VOXEL_MAX_EDGE) throw std::invalid_argument("occupancyTwin: edge out of range");
  const std::size_t n = std::size_t(edge) * edge * edge;
  if (accum.size() < n) throw std::invalid_argument("occupancyTwin: accumulation buffer smaller than the grid");
  // Along x: the distance to the nearest filled voxel of the row, clamped.
  std::vector<std::uint8_t> d(n);
  for (std::size_t r = 0; r < n / edge; ++r)
    for (unsigned x = 0; x < edge; ++x) {
      unsigned best = ML_OCC_MAX_DISTANCE;
      for (unsigned u = 0; u < edge; ++u)
        if (accum[r * edge + u].albedo_count[3] != 0) best = std::min(best, x > u ? x - u : u - x);
      d[r * edge + x] = std::uint8_t(best);
    }
  return linePass(linePass(d, edge, edge), edge, std::size_t(edge) * edge);
}

}  // namespace ml::vct
