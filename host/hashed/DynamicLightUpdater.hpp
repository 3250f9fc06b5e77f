#pragma once
// Incremental updates of a HashedStructure (thesis future work §8.2.3,
// Tables 8.1/8.2). Contract, per call with the new light array:
//  1. Diff by index against the current lights: moved/resized (position or
//     radius differ), added (indices past the old count), removed (indices
//     past the new count). Colour-only changes need nothing: shaders read
//     colours from the light buffer.
//  2. Build the new versions' light octrees (the old ones are cached). A
//     moved light's old and new octrees are walked together over the scene
//     octree, adding and removing its index only where they differ (Tables
//     8.1/8.2); removed lights are removed, added ones inserted (Table 7.1).
//     Then what became mergeable is merged: the tree is again canonical,
//     i.e. exactly what a fresh build would produce. Without
//     the geometry mask the walk computes each version's coverage per
//     node instead (LightCells), and no octree is built or cached.
//  3. Re-derive the hash entries of the touched nodes and edit the tables in
//     place; a table is rehashed only when an insert cannot be placed even by
//     re-offsetting its group (see PerfectSpatialHash). Then rewrite in place
//     the octant masks of moved lights in the untouched deepest leaves
//     (OctantMask.hpp): a moved light's masks change over its whole
//     surface, not only where its sets did. They are found meanwhile step 2.
//  Threads: the tree edits are sequential; the versions' LightCells, or the
//  new octrees, are computed in parallel first. Meanwhile the previous update's
//  light index list garbage is compacted and the octant rewrites are found.
//  Step 3 derives the touched keys in parallel, interns the light sets in
//  key order, then edits each table in its own task. The result does not
//  depend on the thread count.
#include <cstdint>
#include <vector>

#include "host/hashed/HashedStructure.hpp"
#include "host/hashed/OctantMask.hpp"

namespace ml::hashed {

class DynamicLightUpdater {
 public:
  static void apply(HashedStructure& s, const std::vector<gpu::PointLight>& lights, UpdateStats& stats);

 private:
  // Step 1: the moved lights (ascending); counts into `stats`.
  static std::vector<std::uint32_t> diff(const std::vector<gpu::PointLight>& old,
                                         const std::vector<gpu::PointLight>& lights, UpdateStats& stats);
  // Step 3's octant mask rewrites of the moved lights (reads no tree).
  static std::vector<OctantRewrite> findRewrites(const HashedStructure& s, const std::vector<gpu::PointLight>& lights,
                                                 const std::vector<std::uint32_t>& moved);
  // Step 2, recording the touched keys (returned sorted); timed into `stats`.
  static std::vector<std::uint64_t> editTree(HashedStructure& s, const std::vector<gpu::PointLight>& lights,
                                             const std::vector<std::uint32_t>& moved, UpdateStats& stats);
  // Step 2 without the geometry mask: each changed light's old and new
  // cells are compared per node as LightCells, so no octree is built
  // (building the new octrees and their subtree ends was ~35% of an
  // update).
  static void editByCells(HashedStructure& s, const std::vector<gpu::PointLight>& lights,
                          const std::vector<std::uint32_t>& moved);
  // Step 2 with the geometry mask (geometry-tight sets), by light octrees (the old versions'
  // from the cache). Returns the ms spent building the new octrees.
  static double editByOctrees(HashedStructure& s, const std::vector<gpu::PointLight>& lights,
                              const std::vector<std::uint32_t>& moved);
};

}  // namespace ml::hashed
