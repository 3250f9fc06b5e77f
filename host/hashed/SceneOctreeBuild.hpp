#pragma once
// The full build's middle stages (thesis Fig. 7.14): every light's octree and
// the Table 7.1 merge of them into a new scene octree. Contract:
//  - The lights are taken in Morton order of their centre cells, in chunks:
//    the chunks' octrees are built in parallel while the merge (serial: one
//    tree) inserts the finished chunks in that order, so it overlaps the
//    builds instead of waiting for all of them.
//  - The tree, after SceneOctree::normalize(), is the one inserting the
//    lights in any order gives (the canonical form depends only on the light
//    set): the same for any thread count (hashed_build_threads_test).
//  - `check_lit` sees the running count of lit (light, cell) pairs before each
//    chunk is merged and may throw to stop the build before the merge grows
//    past a memory limit (the count only grows, so the last call sees the total).
#include <cstddef>
#include <functional>
#include <memory>
#include <vector>

#include "host/hashed/GeometryMask.hpp"
#include "host/hashed/LightOctreeBuilder.hpp"
#include "host/hashed/OctreeBounds.hpp"
#include "host/hashed/SceneOctree.hpp"

namespace ml::hashed {

struct SceneOctreeBuild {
  std::unique_ptr<SceneOctree> tree;
  std::vector<LightOctree> octrees;  // octrees[i] of lights[i] when kept, else empty
  std::size_t filled_cells = 0;      // lit (light, cell) pairs, summed
  double merge_ms = 0;               // the merge's own time (it overlaps the octree builds)
};

// `order`: mortonOrder(lights, bounds) when the caller made it (beside the
// geometry mask), else null.
SceneOctreeBuild buildSceneOctree(const std::vector<gpu::PointLight>& lights, const OctreeBounds& bounds,
                                  const GeometryMask* mask, bool keep_octrees,
                                  const std::function<void(std::size_t)>& check_lit,
                                  const std::vector<std::uint32_t>* order = nullptr);

// The light indices in Morton order of their centre cells (coarsened to at
// most 10 bits an axis; centres outside the bounds clamped), ties by index.
std::vector<std::uint32_t> mortonOrder(const std::vector<gpu::PointLight>& lights, const OctreeBounds& bounds);

}  // namespace ml::hashed
