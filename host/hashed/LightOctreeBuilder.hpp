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
//    sphere reaches the geometry inside it (GeometryMask::geometryBox); cells
//    without geometry cannot be lit and may join full nodes. That predicate
//    is not convex in the cell position, so the flood fill and the decision
//    tree's closest/farthest shortcuts give way to testing every cell of the
//    grid and merging bottom-up; the result is still a minimal octree.
#include <glm/glm.hpp>

#include <array>
#include <cstdint>
#include <vector>

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

// Scratch space reused across lights by one thread (the grid).
struct LightGridScratch {
  std::vector<std::uint8_t> grid;
  std::vector<std::uint32_t> queue;
};

LightOctree buildLightOctree(const gpu::PointLight& light, std::uint32_t index, const OctreeBounds& bounds,
                             LightGridScratch& scratch, const GeometryMask* geometry = nullptr);

// Every light's octree, built in parallel (TBB); out[i] belongs to lights[i].
std::vector<LightOctree> buildLightOctrees(const std::vector<gpu::PointLight>& lights, const OctreeBounds& bounds,
                                           const GeometryMask* geometry = nullptr);

// Skips the preorder subtree starting at `cursor`.
inline void skipLightSubtree(const LightNode*& cursor) {
  std::uint32_t pending = 1;
  while (pending) {
    --pending;
    if (*cursor++ == LightNode::Branch) pending += 8;
  }
}

}  // namespace ml::hashed
