#pragma once
// Everything hashed shading keeps on the host for one light set: octree
// bounds, the optional geometry mask, the scene octree and its linkless form.
// Contract:
//  - build() is the thesis's pipeline (Fig. 7.14): bounds -> per-light grids
//    and octrees (parallel) overlapped with the Table 7.1 merge into the scene octree ->
//    canonical merge (relaxed by geometry when masked) -> per-layer perfect
//    spatial hashes (parallel) -> light index list. Timed per stage.
//  - update() applies a new light array incrementally (DynamicLightUpdater):
//    afterwards lookups equal those of build() on the same array with the
//    same bounds. It falls back to build() when a light leaves the bounds,
//    when there was no build, or when more than `max_incremental_fraction`
//    of the lights changed (a rebuild is then cheaper).
//  - Lights are identified by index: to remove light i cheaply, move the last
//    light into slot i and shrink the array (two edits instead of n - i).
#include <memory>
#include <string>
#include <vector>

#include "host/hashed/GeometryMask.hpp"
#include "host/hashed/LightOctreeBuilder.hpp"
#include "host/hashed/LinklessOctree.hpp"
#include "host/hashed/OctreeBounds.hpp"
#include "host/hashed/SceneOctree.hpp"
#include "host/scene/Scene.hpp"

namespace ml::hashed {

struct BuildStats {
  // light_octrees_ms: the light octrees and the merge, which overlap (wall
  // time, SceneOctreeBuild.hpp); merge_ms: the merge's own share of it;
  // mask_ms: the geometry mask, with the lights' Morton order made beside it.
  double bounds_ms = 0, mask_ms = 0, light_octrees_ms = 0, merge_ms = 0, normalize_ms = 0, hash_ms = 0,
         total_ms = 0;
  std::size_t filled_cells = 0;        // (light, cell) overlaps, summed
  std::size_t scene_nodes = 0;
  std::size_t index_entries = 0;       // light index list length (distinct sets stored once)
  std::size_t leaf_index_entries = 0;  // what the list would hold without sharing
  std::size_t mask_cells = 0;
  std::size_t mask_bytes = 0;          // the mask build's peak (its own count)
};

struct UpdateStats {
  bool full_rebuild = false;
  std::string reason;  // why a full rebuild happened
  std::size_t moved = 0, added = 0, removed = 0;
  double light_octrees_ms = 0, tree_ms = 0, sync_ms = 0, total_ms = 0;
  SyncStats sync;
};

class HashedStructure {
 public:
  explicit HashedStructure(const HashedConfig& config, const Scene* scene = nullptr);
  ~HashedStructure();

  void build(const std::vector<gpu::PointLight>& lights);
  void build(const std::vector<gpu::PointLight>& lights, const OctreeBounds& bounds);
  const UpdateStats& update(const std::vector<gpu::PointLight>& lights);
  // Index list entries hold the light in 24 bits (OctantMask.hpp): more
  // lights are a UserError naming --lights (build() and update() check).
  static void checkLightCount(std::size_t lights);

  bool built() const { return linkless_ != nullptr; }
  const HashedConfig& config() const { return cfg_; }
  const OctreeBounds& bounds() const { return bounds_; }
  const LinklessOctree& linkless() const { return *linkless_; }
  LinklessOctree& linkless() { return *linkless_; }  // uploaders take its dirty records
  const SceneOctree& tree() const { return *tree_; }
  // The geometry mask, which the light octrees test against (geometry-tight
  // light sets), or null.
  const GeometryMask* mask() const { return mask_.get(); }
  // With the geometry mask, every light's octree as the build kept it
  // (lightOctrees()[i] of lights()[i]); empty without it.
  const std::vector<LightOctree>& lightOctrees() const { return octrees_; }
  const std::vector<gpu::PointLight>& lights() const { return lights_; }
  const BuildStats& lastBuild() const { return build_stats_; }
  const UpdateStats& lastUpdate() const { return update_stats_; }
  std::size_t buildCount() const { return builds_; }

 private:
  friend class DynamicLightUpdater;
  // The geometry mask of the scene at `bounds`; UserError naming --node-size
  // when it passes the memory limit.
  std::unique_ptr<GeometryMask> buildMask(const OctreeBounds& bounds) const;
  HashedConfig cfg_;
  const Scene* scene_;
  OctreeBounds bounds_;
  std::unique_ptr<GeometryMask> mask_;
  std::unique_ptr<SceneOctree> tree_;
  std::unique_ptr<LinklessOctree> linkless_;
  std::vector<gpu::PointLight> lights_;
  // With the geometry mask, each light's octree, kept (the thesis's option
  // 3) so that an update only builds the octrees of the lights' new
  // versions; empty otherwise (updates compare LightCells instead).
  std::vector<LightOctree> octrees_;
  BuildStats build_stats_;
  UpdateStats update_stats_;
  std::size_t builds_ = 0;
};

}  // namespace ml::hashed
