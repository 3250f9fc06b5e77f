#pragma once
// One light as an octree (thesis §7.2.3, Fig. 7.11-7.13). Contract:
//  - First the light's minimal grid: the cells of its (clamped) cell box, all
//    assumed to overlap the sphere, then a breadth-first flood fill from the
//    box's 8 corners marks the cells that do not (a cell outside the sphere
//    is reachable from its octant's corner through cells outside the sphere,
//    so the fill finds them all).
//  - Then the octree, top-down by the thesis's decision tree. One departure:
//    the thesis roots it at the smallest node enclosing the grid, which for
//    a grid straddling a coarse boundary is far larger than the light and
//    fills the octree with empty siblings; here the roots are the (at most
//    8) nodes at the deepest depth where the grid spans at most 2 nodes per
//    axis, empty ones dropped. Per root the decision tree is the thesis's: a node is an empty leaf when the grid
//    cell in it closest to the light is empty (spheres are convex), a full
//    leaf when it lies inside the grid and the farthest cell is full too,
//    else a branch. The result is the minimal octree of the light's cells.
//  - Stored compactly in preorder (1 byte per node), children in bit order
//    k = x + 2y + 4z, so the scene octree can walk it without pointers.
//  - With a geometry mask (beyond the thesis), a cell is filled only when the
//    sphere reaches the geometry inside it (GeometryMask::octantBoxes); cells
//    without geometry cannot be lit and may join full nodes. That predicate
//    is not convex in the cell position, so the flood fill and the decision
//    tree's closest/farthest shortcuts give way to testing every cell of the
//    grid; a node is then a branch exactly when it holds a lit cell and an
//    unlit one (or one outside the grid), read from the grid's box counts,
//    so the result is still a minimal octree.
#include <glm/glm.hpp>

#include <algorithm>
#include <array>
#include <cstdint>
#include <vector>

#include "host/hashed/EightSums.hpp"
#include "host/hashed/GeometryMask.hpp"
#include "host/hashed/OctreeBounds.hpp"

namespace ml::hashed {

enum class LightNode : std::uint8_t { Empty = 0, Full = 1, Branch = 2 };

struct LightOctree {
  std::uint32_t light = 0;
  unsigned root_depth = 0;
  unsigned root_count = 0;                    // 0: the light touches no cell
  std::array<glm::uvec3, 8> roots{};           // coordinates at root_depth
  std::array<std::uint32_t, 8> root_start{};   // where each root's preorder subtree starts in `nodes`
  std::vector<LightNode> nodes;                // preorder subtrees, one after the other
  std::size_t filled_cells = 0;                // grid cells overlapping the sphere
  bool empty() const { return root_count == 0; }
};

// The decision tree above for the node with min corner `rlo` and edge
// `size` (cells), against a light whose cells are those of its cell box
// [glo, ghi] for which `filled` holds (a convex set). Shared by the builder
// (filled: its grid) and LightCells (filled: the overlap test itself).
// Always inlined, as it was in the builder before it was shared: a call per
// node made the full build a few percent slower.
template <class Filled>
[[gnu::always_inline]] inline LightNode classifyNode(const glm::ivec3& rlo, int size, const glm::ivec3& glo,
                                                     const glm::ivec3& ghi, const glm::ivec3& centre_cell,
                                                     const glm::dvec3& twice_centre, const Filled& filled) {
  const glm::ivec3 rhi = rlo + (size - 1);
  const glm::ivec3 ilo = glm::max(rlo, glo), ihi = glm::min(rhi, ghi);
  if (ilo.x > ihi.x || ilo.y > ihi.y || ilo.z > ihi.z) return LightNode::Empty;
  // Closest cell: per axis the one nearest the centre (distances add up per axis).
  const glm::ivec3 closest = glm::clamp(centre_cell, ilo, ihi);
  if (!filled(closest)) return LightNode::Empty;
  if (size == 1) return LightNode::Full;
  if (ilo == rlo && ihi == rhi) {
    // Farthest: per axis the end whose far face is farther from the centre.
    glm::ivec3 farthest;
    for (int a = 0; a < 3; ++a) farthest[a] = twice_centre[a] >= double(ilo[a] + ihi[a] + 1) ? ilo[a] : ihi[a];
    if (filled(farthest)) return LightNode::Full;
  }
  return LightNode::Branch;
}

// A light's cells as buildLightOctree() without geometry has them, node by
// node, without building its grid or octree: cover(t, c) is Empty when the
// light fills none of node (t, c)'s cells, Full when it fills all, else
// Branch. Where the light's octree has node (t, c), it says the same; above
// its roots a node may read Full where the octree has full roots. Exact:
// the builder's flood fill leaves filled exactly the box cells that pass
// sphereOverlapsCells(), which cover() evaluates (summing the same per-axis
// terms in the same order) under the builder's own decision tree. A
// default-constructed one fills nothing (a light added or removed).
class LightCells {
 public:
  LightCells() = default;
  LightCells(const gpu::PointLight& light, const OctreeBounds& bounds);
  LightNode cover(unsigned t, const glm::uvec3& c) const {
    const int shift = int(depth_ - t);
    return classifyNode(glm::ivec3(c) << shift, 1 << shift, box_.lo, box_.hi, centre_cell_, twice_centre_,
                        [this](const glm::ivec3& p) { return filled(p); });
  }

  // cover() of the 8 children of node (t, c), for children of at least 2
  // cells a side: bit k of `full` / `branch` says child k is Full / Branch
  // (neither: Empty). The same per-axis terms and decisions as cover(), per
  // axis and child half, with the 8 sums at once (EightSums.hpp): the
  // update walk asks this of every node it descends through.
  void childCovers(unsigned t, const glm::uvec3& c, std::uint8_t& full, std::uint8_t& branch) const {
    const int s = 1 << (depth_ - t - 1);
    double near[3][2], far[3][2];
    for (int a = 0; a < 3; ++a)
      for (int j = 0; j < 2; ++j) {
        const int rlo = (2 * int(c[a]) + j) * s, rhi = rlo + s - 1;
        const int ilo = std::max(rlo, box_.lo[a]), ihi = std::min(rhi, box_.hi[a]);
        if (ilo > ihi) {
          near[a][j] = far[a][j] = kFar;
          continue;
        }
        const double* d = axis_d2_.data() + axis_off_[a] - box_.lo[a];
        near[a][j] = d[std::clamp(centre_cell_[a], ilo, ihi)];
        far[a][j] = ilo == rlo && ihi == rhi ? d[twice_centre_[a] >= double(ilo + ihi + 1) ? ilo : ihi] : kFar;
      }
    const std::uint8_t filled = eightSumsBelow(near[0], near[1], near[2], r2_);
    full = filled & eightSumsBelow(far[0], far[1], far[2], r2_);
    branch = filled & std::uint8_t(~full);
  }

  // The deepest cells the light may reach (empty: no version).
  const CellBox& box() const { return box_; }

  // Bit k: cover() of child k of the node (depth - 1, c), i.e. of its 2x2x2
  // cells: Full (1) or Empty (0). Branch-free: the update walk asks this of
  // every node above the cells on both versions' surfaces.
  std::uint8_t cellMask(const glm::uvec3& c) const {
    double d[3][2];
    for (int a = 0; a < 3; ++a)
      for (int j = 0; j < 2; ++j) {
        const int x = int(2 * c[a]) + j, i = x - box_.lo[a];
        d[a][j] = x >= box_.lo[a] && x <= box_.hi[a] ? axis_d2_[std::size_t(axis_off_[a] + i)] : kFar;
      }
    return eightSumsBelow(d[0], d[1], d[2], r2_);
  }

 private:
  static constexpr double kFar = 1e300;  // outside the box: never within the radius
  // sphereOverlapsCells(p, p) for a cell p of the box, from per-axis squared
  // distances summed in the same order (the same double, bit for bit).
  bool filled(const glm::ivec3& p) const {
    const double* d = axis_d2_.data();
    return d[p.x - box_.lo.x] + d[axis_off_.y + p.y - box_.lo.y] + d[axis_off_.z + p.z - box_.lo.z] < r2_;
  }
  CellBox box_;
  glm::ivec3 centre_cell_{0};  // floor(centre), clamped to the box
  glm::dvec3 twice_centre_{0.0};
  double r2_ = 0.0;
  unsigned depth_ = 0;
  glm::ivec3 axis_off_{0};        // where each axis starts in axis_d2_
  std::vector<double> axis_d2_;  // per axis and box cell: squared distance from the centre
};

// Scratch space reused across lights by one thread (the grid and its counts).
struct LightGridScratch {
  std::vector<std::uint8_t> grid;
  std::vector<std::uint32_t> queue;
  std::vector<std::uint64_t> sums;  // the grid's summed-volume table (with a geometry mask)
};

LightOctree buildLightOctree(const gpu::PointLight& light, std::uint32_t index, const OctreeBounds& bounds,
                             LightGridScratch& scratch, const GeometryMask* geometry = nullptr);

// (Every light's octree of a full build: buildSceneOctree(), SceneOctreeBuild.hpp.)

// Skips the preorder subtree starting at `cursor`.
inline void skipLightSubtree(const LightNode*& cursor) {
  std::uint32_t pending = 1;
  while (pending) {
    --pending;
    if (*cursor++ == LightNode::Branch) pending += 8;
  }
}

}  // namespace ml::hashed
