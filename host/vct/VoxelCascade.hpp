#pragma once
// Where the levels of seed 002's camera-centred cascade lie (--vct-cascades
// L), and what a level must voxelize again when the camera moves.
// Contract:
//  - Level L - 1, the outermost, is the grid fitted around the scene
//    (fitVoxelGrid, unscrolled, the settings' levels): it holds the whole
//    scene from any viewpoint, so a cone never leaves the volume before it
//    would leave the scene (the reference sees the whole scene too). With
//    L = 1 it is the only level: the single grid. With L > 1 and `nested`
//    (--vct-fold) its corner is moved to the nearest point of its voxel
//    lattice (less than half a voxel; fitVoxelGrid leaves one voxel around
//    the scene), so every level's voxels nest in the next level's
//    (CascadeFold.hpp); without, the inner levels' lattices need not meet
//    its voxels' faces.
//  - Level c < L - 1 is a v^3 toroidal grid (VoxelGridParams::wrap) of
//    voxel size s / 2^(L - 1 - c), s the outermost's, so each level spans
//    twice the extent of the one inside it; its corner lies on the lattice
//    of its voxel size, kInnerStep-aligned, at the lattice point nearest to
//    the eye minus half the window: the eye sits within one voxel of its
//    centre. Inner levels keep kInnerLevels mip levels: a cone reads the
//    finest level whose mips reach its footprint, then the next level's
//    (vct_cones.glsl).
//  - scrollRegion(before, after): the slabs of `after`'s window that were
//    not in `before`'s (window coordinates, up to one box per axis), or
//    `full` when the two are not the same toroidal grid moved by less than
//    its edge (first placement, other size, a jump).
//  - checkCascades(): UserError naming --vct-cascades outside 1..kMaxCascades.
#include <glm/glm.hpp>

#include <cstddef>
#include <vector>

#include "host/scene/Scene.hpp"
#include "host/shared/voxel_types.h"
#include "host/vct/VoxelGrid.hpp"
#include "host/vct/VoxelRegion.hpp"

namespace ml::vct {

// Seven textures a level (isotropic + 6 directions), and GL promises 32
// compute texture units on the GPUs this targets: 4 levels and the G-buffer.
inline constexpr unsigned kMaxCascades = 4;
// 2 mip levels (corner on a 2-voxel lattice): the fine level's own mips
// serve footprints one level up, then the coarser level's separate
// voxelization takes over. Flights, 2 x 64^3 against one 64^3 grid
// (docs/vct.md, "The flight"): with 2 the cascade is lower at 12 of 12
// cameras; with 3 it lost at Spaceship Indoor's camera 4 (0.267 against
// 0.250; 0.218 with 2), a ribbed wall panel 3 m ahead that read 1.14x the
// reference's energy: the inner level's second mip passes light that the
// coarser level's own voxelization of the ribs stops. Default scene means
// 0.161 with 2, 0.155 with 3, 0.173 reading only the inner level's finest
// voxels (bench/RESULTS-vct.md, "Inner cascade levels with 2 mip levels").
inline constexpr unsigned kInnerLevels = 2;
inline constexpr unsigned kInnerStep = 1u << (kInnerLevels - 1);  // corner alignment, voxels

void checkCascades(unsigned cascades);

// A level's corner as lattice indices of its voxel size (corner / voxel,
// rounded): what placement snaps to, scrolls count and CascadeFold nests.
struct LatticeCorner {
  long long x, y, z;
};
LatticeCorner latticeCorner(const gpu::VoxelGridParams& g);

// The settings of level c of `cascades` (voxels, anisotropic as `s`).
VoxelGridSettings cascadeLevelSettings(const VoxelGridSettings& s, unsigned cascades, unsigned c);
// Device memory of every level (voxelBytes of each).
std::size_t cascadeBytes(const VoxelGridSettings& s, unsigned cascades);

// nested (--vct-fold): the outermost level's corner on its lattice, see above.
std::vector<gpu::VoxelGridParams> placeCascade(const Aabb& scene_bounds, const VoxelGridSettings& s,
                                               unsigned cascades, const glm::vec3& eye, bool nested = false);

// Level c < cascades - 1 of the cascade whose outermost level is `outer`:
// the toroidal grid around `eye` that placeCascade() puts there.
gpu::VoxelGridParams innerCascadeLevel(const gpu::VoxelGridParams& outer, const VoxelGridSettings& s,
                                       unsigned cascades, unsigned c, const glm::vec3& eye);

struct ScrollUpdate {
  bool full = true;
  VoxelRegion region;  // empty when nothing moved (and not full)
};
ScrollUpdate scrollRegion(const gpu::VoxelGridParams* before, const gpu::VoxelGridParams& after);

}  // namespace ml::vct
