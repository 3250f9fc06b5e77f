#include "host/vct/VoxelGrid.hpp"

#include <algorithm>
#include <string>

#include "host/util/Error.hpp"

namespace ml::vct {

namespace {
bool isPow2(unsigned v) { return v && !(v & (v - 1)); }
}  // namespace

unsigned log2Exact(unsigned pow2) {
  unsigned k = 0;
  while ((1u << k) < pow2) ++k;
  return k;
}

unsigned autoLevels(unsigned voxels) {
  const unsigned k = log2Exact(voxels);
  return k > 2 ? k - 1 : 1;
}

void checkVoxelGrid(const VoxelGridSettings& s) {
  if (!isPow2(s.voxels) || s.voxels > ML_VOXEL_MAX_EDGE)
    throw UserError("--voxels " + std::to_string(s.voxels) + ": must be a power of two from 1 to " +
                    std::to_string(ML_VOXEL_MAX_EDGE));
  const unsigned most = log2Exact(s.voxels) + 1;
  if (s.levels < 1 || s.levels > most)
    throw UserError("--levels " + std::to_string(s.levels) + ": must be 1.." + std::to_string(most) + " for --voxels " +
                    std::to_string(s.voxels) + " (each level halves the edge, down to 1 voxel)");
}

std::size_t voxelsAllLevels(unsigned edge, unsigned levels) { return gpu::voxel_level_offset(edge, levels); }

std::size_t voxelsCoarseLevels(unsigned edge, unsigned levels) {
  return levels ? voxelsAllLevels(edge, levels) - std::size_t(edge) * edge * edge : 0;
}

std::size_t accumBytes(const VoxelGridSettings& s) {
  return std::size_t(s.voxels) * s.voxels * s.voxels * sizeof(gpu::VoxelAccum);
}

std::size_t radianceBytes(const VoxelGridSettings& s) { return voxelsAllLevels(s.voxels, s.levels) * 16; }

std::size_t anisotropicBytes(const VoxelGridSettings& s) {
  return s.anisotropic ? voxelsCoarseLevels(s.voxels, s.levels) * ML_VOXEL_DIRECTIONS * 16 : 0;
}

std::size_t voxelBytes(const VoxelGridSettings& s) { return accumBytes(s) + radianceBytes(s) + anisotropicBytes(s); }

gpu::VoxelGridParams fitVoxelGrid(const Aabb& bounds, const VoxelGridSettings& s) {
  checkVoxelGrid(s);
  glm::vec3 lo(-0.5f), hi(0.5f);
  if (!bounds.empty()) {
    lo = bounds.min;
    hi = bounds.max;
  }
  const glm::vec3 extent = hi - lo;
  const float longest = std::max({extent.x, extent.y, extent.z, 1e-6f});
  // `voxels` cells cover the longest side plus one cell on each end.
  const float cell = longest / float(std::max(1u, s.voxels - std::min(s.voxels - 1, 2u)));
  const glm::vec3 origin = 0.5f * (lo + hi) - glm::vec3(0.5f * cell * float(s.voxels));
  gpu::VoxelGridParams p{};
  p.origin_voxel_size = {origin.x, origin.y, origin.z, cell};
  p.edge = s.voxels;
  p.levels = s.levels;
  return p;
}

}  // namespace ml::vct
