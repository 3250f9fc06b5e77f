#pragma once
// The GPU form of the scene octree [CJC09] (thesis §7.1.5, §7.2.5): per layer
// i = 0 .. depth - start_depth - 1 two perfect spatial hashes,
//   desc[i]: key = a branch at depth start_depth + i -> leaf/filled masks of
//            its 8 children (nodes at the start depth absent from desc[0]
//            hold no lights),
//   data[i]: key = a filled leaf at depth start_depth + i + 1 -> its range in
//            the light index list,
// plus the light index list, whose entries carry octant masks (OctantMask.hpp).
// Contract:
//  - lookup() is lookup_hashed.glsl's lightListFor, in the same order and the
//    same float expression for the cell; tests hold the GLSL to it through
//    images and counts. cellAt() is the same walk, reporting the node it ends in.
//  - buildFrom() hashes every layer of a canonical scene octree (layers in
//    parallel); applyTouched() re-derives only the given node keys and edits
//    the hashes in place (rehashing a table only when an insert cannot be
//    placed): afterwards every lookup equals that of buildFrom() on the same
//    tree and lights, provided applyOctantRewrites() preceded it with the
//    moved lights' octant changes. Deepest leaves own their ranges when octant
//    masks are on (LightSetPool::acquireOwn), so that a changed mask is a
//    one-word rewrite; other ranges are shared between equal sets.
//  - The GPU image: a header (origin, scale, depth, start depth, layer count,
//    then per layer and table (desc, data) the hash table's dimensions and
//    slot base, and the offset table's dimensions and offset base),
//    one offset buffer, one desc slot buffer (uvec2) and one data slot buffer
//    (uvec4), all layers concatenated. layoutVersion() changes whenever a
//    table's size (and so any base) changes.
#include <glm/glm.hpp>

#include <cstdint>
#include <vector>

#include "host/hashed/LightSetPool.hpp"
#include "host/hashed/OctantMask.hpp"
#include "host/hashed/OctreeBounds.hpp"
#include "host/hashed/PerfectSpatialHash.hpp"
#include "host/hashed/SceneOctree.hpp"
#include "host/hashed/TableEdits.hpp"

namespace ml::hashed {

struct LayerStats {
  unsigned depth = 0;               // depth of the desc keys
  std::size_t desc_keys = 0, data_keys = 0;
  std::size_t desc_slots = 0, data_slots = 0;      // m^3
  std::size_t desc_offsets = 0, data_offsets = 0;  // r^3
  std::size_t bytes = 0;
  unsigned desc_attempts = 0, data_attempts = 0;
  std::uint64_t rejected_candidates = 0;
  double hash_ms = 0.0;
};

struct SyncStats {
  std::size_t keys = 0;            // touched keys examined
  std::size_t inserts = 0, updates = 0, erases = 0;
  std::size_t in_place = 0, reoffsets = 0;  // how the inserts were placed
  std::size_t rehashed_tables = 0;
  bool compacted = false;
};

class LinklessOctree {
 public:
  // `geometry` (may be null; must outlive this) reduces the octant masks
  // (OctantMask.hpp).
  LinklessOctree(const OctreeBounds& bounds, const HashedConfig& config, const GeometryMask* geometry = nullptr);

  void buildFrom(const SceneOctree& tree, const std::vector<gpu::PointLight>& lights);
  // Octant masks in an update, before applyTouched(): find (read-only, e.g.
  // while the tree is edited) the list words that the moved lights' octant
  // changes alter, then rewrite them. `changes` must hold every deepest cell
  // where a moved light's mask changed and that does not become a touched
  // key (appendOctantChanges()). (`changes` is sorted in the process.)
  std::vector<OctantRewrite> findOctantRewrites(std::vector<OctantChange>& changes) const;
  void applyOctantRewrites(const std::vector<OctantRewrite>& rewrites);
  // A touched deepest leaf keeps the words of the lights it listed already:
  // with the rewrites above applied first, their masks are current.
  void applyTouched(const SceneOctree& tree, const std::vector<gpu::PointLight>& lights,
                    const std::vector<std::uint64_t>& touched, SyncStats& stats);
  // Repacks the light index list when its garbage calls for it (and remaps
  // the data tables); lookups are unchanged. applyTouched() leaves this to
  // the caller, which may run it while it edits the scene octree for the
  // next update (neither touches the other's state). True if it compacted.
  bool compactIfWanted();

  // The point's leaf entries and its octant (entries without that octant's
  // bit are skipped); lightsAt() is the lights the shader evaluates.
  struct Range {
    std::uint32_t offset = 0, count = 0;
    unsigned octant = 0;
  };
  Range lookup(const glm::vec3& world) const;
  std::vector<std::uint32_t> lightsAt(const glm::vec3& world) const;
  // The node lookup() ends in for `world` (the octree-cell debug view):
  // Filled, a leaf at depth start_depth + 1 or deeper that lists lights
  // (`range`); Empty, a leaf that lists none, or the start-depth node when
  // it holds no lights (the tables store nothing above it); Outside the cube.
  struct Cell {
    enum class Kind : std::uint8_t { Outside, Empty, Filled };
    Kind kind = Kind::Outside;
    unsigned depth = 0;
    glm::uvec3 coord{0u};
    Range range{};
  };
  Cell cellAt(const glm::vec3& world) const;

  const OctreeBounds& bounds() const { return b_; }
  unsigned layerCount() const { return unsigned(desc_.size()); }
  const DescHash& desc(unsigned i) const { return desc_[i]; }
  const DataHash& data(unsigned i) const { return data_[i]; }
  LightSetPool& pool() { return pool_; }
  const LightSetPool& pool() const { return pool_; }
  std::vector<LayerStats> layerStats() const;
  std::size_t tableBytes() const;
  std::size_t gpuBytes() const;  // tables + header + light index list

  // GPU image.
  std::uint64_t layoutVersion() const { return layout_version_; }
  // Table `layer`'s desc (data: false) or data hash's edits since the last
  // take (all of it after a build, rehash or compaction).
  TableEdits takeEdits(unsigned layer, bool data);
  std::vector<std::uint32_t> headerWords() const;
  // The whole image as lookup_hashed.glsl binds it (the light index list is
  // pool().list()): what a full upload writes, and what kernels read.
  struct GpuImage {
    std::vector<std::uint32_t> header, offsets, desc, data;
  };
  GpuImage packGpuImage() const;
  // Where each table starts in the concatenated arrays: offsets in words, slots in slots.
  std::size_t offsetBase(unsigned layer, bool data) const { return offset_base_[2 * layer + (data ? 1 : 0)]; }
  std::size_t descSlotBase(unsigned layer) const { return desc_base_[layer]; }
  std::size_t dataSlotBase(unsigned layer) const { return data_base_[layer]; }
  std::size_t offsetWordCount() const { return offset_base_.back(); }
  std::size_t descSlotCount() const { return desc_base_.back(); }
  std::size_t dataSlotCount() const { return data_base_.back(); }

 private:
  void computeBases();
  void hashTables(const std::vector<std::vector<DescHash::Entry>>& desc_entries,
                  const std::vector<std::vector<DataHash::Entry>>& data_entries);
  // A filled leaf of the tree being built.
  struct LeafRef {
    unsigned t;
    glm::uvec3 c;
    const std::vector<std::uint32_t>* set;
  };
  // buildFrom()'s index list: every leaf's entries interned in tree order
  // (offsets do not depend on threads); per leaf its range in the list.
  std::vector<DataTraits::Payload> internLeaves(const std::vector<LeafRef>& leaves,
                                                const std::vector<gpu::PointLight>& lights);
  bool ownsRange(unsigned t) const { return cfg_.octant_masks && t == b_.depth; }
  // A leaf's index list entries: its lights with their octant masks,
  // computed per (light, cell) rather than read from per-light tables (those
  // were a third of a large build's peak memory for no measurable time; with
  // the geometry mask each entry needs the light's terms anyway); with
  // `reuse`, the entries of lights already in the leaf's range are copied from it.
  struct Reuse {
    const std::uint32_t *first = nullptr, *last = nullptr;
  };
  void entriesOf(unsigned t, const glm::uvec3& c, const std::uint32_t* set, std::size_t n,
                 const std::vector<gpu::PointLight>& lights, const Reuse* reuse,
                 std::vector<std::uint32_t>& out) const;
  // applyTouched()'s phases: derive what each touched key wants (parallel,
  // with own ranges rewritten in place), plan the edits per table (interning
  // sets in key order), write the tables (one task each).
  struct Derived;
  struct DeriveScratch;
  struct ScratchPerThread;  // a DeriveScratch per thread, taken only when needed
  struct Plan;
  std::vector<Derived> deriveTouched(const SceneOctree& tree, const std::vector<gpu::PointLight>& lights,
                                     const std::vector<std::uint64_t>& touched);
  void deriveData(unsigned t, const glm::uvec3& c, const SceneOctree::NodeView& v,
                  const std::vector<gpu::PointLight>& lights, Derived& d, ScratchPerThread& sc);
  void rewriteInPlace(unsigned t, const glm::uvec3& c, const std::vector<std::uint32_t>& set,
                      const DataTraits::Payload& have, const std::vector<gpu::PointLight>& lights,
                      DeriveScratch& sc);
  Plan planEdits(const std::vector<std::uint64_t>& touched, const std::vector<Derived>& derived);
  void writeTables(const Plan& plan, SyncStats& stats);
  template <class Hash, class Ops>
  bool editTable(Hash& table, const Ops& ops, unsigned task, SplitMix64& rng, SyncStats& stats);

  OctreeBounds b_;
  HashedConfig cfg_;
  const GeometryMask* geometry_;
  std::vector<DescHash> desc_;
  std::vector<DataHash> data_;
  std::vector<TableEdits> edits_;  // per table: desc 2i, data 2i + 1
  std::vector<LayerStats> build_stats_;
  LightSetPool pool_;
  SplitMix64 rng_;
  std::uint64_t layout_version_ = 0;
  std::vector<std::size_t> offset_base_, desc_base_, data_base_;
};

}  // namespace ml::hashed
