#include "host/vct/VoxelCascade.hpp"

#include <cmath>
#include <cstring>
#include <string>

#include "host/util/Error.hpp"

namespace ml::vct {
namespace {

// The corner's lattice index along one axis: the eye's voxel minus half the
// window, rounded to a multiple of kInnerStep.
long long cornerIndex(float eye, float voxel, unsigned edge) {
  const double k = std::floor(double(eye) / voxel) - double(edge) / 2.0;
  return static_cast<long long>(std::llround(k / kInnerStep)) * kInnerStep;
}

}  // namespace

LatticeCorner latticeCorner(const gpu::VoxelGridParams& g) {
  const auto& o = g.origin_voxel_size;
  return {std::llround(double(o.x) / o.w), std::llround(double(o.y) / o.w), std::llround(double(o.z) / o.w)};
}

void checkCascades(unsigned cascades) {
  if (cascades < 1 || cascades > kMaxCascades)
    throw UserError("--vct-cascades " + std::to_string(cascades) + ": must be 1.." + std::to_string(kMaxCascades));
}

VoxelGridSettings cascadeLevelSettings(const VoxelGridSettings& s, unsigned cascades, unsigned c) {
  VoxelGridSettings l = s;
  if (c + 1 < cascades) l.levels = std::min(kInnerLevels, log2Exact(s.voxels) + 1);
  return l;
}

std::size_t cascadeBytes(const VoxelGridSettings& s, unsigned cascades) {
  std::size_t n = 0;
  for (unsigned c = 0; c < cascades; ++c) n += voxelBytes(cascadeLevelSettings(s, cascades, c));
  return n;
}

std::vector<gpu::VoxelGridParams> placeCascade(const Aabb& scene_bounds, const VoxelGridSettings& s,
                                               unsigned cascades, const glm::vec3& eye, bool nested) {
  checkCascades(cascades);
  gpu::VoxelGridParams outer = fitVoxelGrid(scene_bounds, s);
  if (cascades > 1 && nested) {  // on its lattice, so the inner levels' voxels nest in its voxels (CascadeFold)
    auto& o = outer.origin_voxel_size;
    const LatticeCorner k = latticeCorner(outer);
    o.x = float(k.x) * o.w;
    o.y = float(k.y) * o.w;
    o.z = float(k.z) * o.w;
  }
  std::vector<gpu::VoxelGridParams> levels(cascades, outer);
  for (unsigned c = 0; c + 1 < cascades; ++c) levels[c] = innerCascadeLevel(outer, s, cascades, c, eye);
  return levels;
}

gpu::VoxelGridParams innerCascadeLevel(const gpu::VoxelGridParams& outer, const VoxelGridSettings& s,
                                       unsigned cascades, unsigned c, const glm::vec3& eye) {
  const float voxel = outer.origin_voxel_size.w / float(1u << (cascades - 1 - c));
  gpu::VoxelGridParams p = outer;
  p.levels = cascadeLevelSettings(s, cascades, c).levels;
  p.wrap = 1;
  p.origin_voxel_size = {float(cornerIndex(eye.x, voxel, s.voxels)) * voxel,
                         float(cornerIndex(eye.y, voxel, s.voxels)) * voxel,
                         float(cornerIndex(eye.z, voxel, s.voxels)) * voxel, voxel};
  return p;
}

// A move by d voxels along an axis brings in |d| new slices of the window:
// the last d (d > 0) or the first -d (d < 0), across the other two axes.
ScrollUpdate scrollRegion(const gpu::VoxelGridParams* before, const gpu::VoxelGridParams& after) {
  ScrollUpdate u;
  if (before && std::memcmp(before, &after, sizeof(after)) == 0) return ScrollUpdate{false, {}};
  if (!before || !after.wrap || !before->wrap || before->edge != after.edge || before->levels != after.levels ||
      before->origin_voxel_size.w != after.origin_voxel_size.w)
    return u;
  const LatticeCorner kb = latticeCorner(*before), ka = latticeCorner(after);
  const long long moved[3] = {ka.x - kb.x, ka.y - kb.y, ka.z - kb.z};  // same voxel size (checked above)
  const auto edge = static_cast<long long>(after.edge);
  u.full = false;
  for (int axis = 0; axis < 3; ++axis) {
    const long long d = moved[axis];
    if (d == 0) continue;
    if (d >= edge || -d >= edge) return ScrollUpdate{};
    VoxelBox box;
    box.hi = {after.edge, after.edge, after.edge};
    if (d > 0) box.lo[axis] = static_cast<unsigned>(edge - d);
    else box.hi[axis] = static_cast<unsigned>(-d);
    u.region.push_back(box);
  }
  return u;
}

}  // namespace ml::vct
