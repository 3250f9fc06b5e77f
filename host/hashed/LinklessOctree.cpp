#include "host/hashed/LinklessOctree.hpp"

#include "host/hashed/KeySort.hpp"
#include "host/hashed/OctantMask.hpp"

#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_invoke.h>

#include <algorithm>
#include <bit>
#include <optional>
#include <stdexcept>

namespace ml::hashed {
namespace {

// How many lights ahead entriesOf() asks the cache for.
constexpr std::size_t kLightPrefetch = 8;

// Below these sizes a thread hand-off costs more than the work it spreads:
// touched keys derived (applyTouched() step 1), table edits written (step
// 3), keys hashed in a build, index list entries remapped by a compaction.
constexpr std::size_t kParallelDeriveMinKeys = 512;
constexpr std::size_t kParallelTableEditsMinOps = 4096;
constexpr std::size_t kParallelHashMinKeys = 20000;
constexpr std::size_t kParallelRemapMinEntries = 16384;

std::uint64_t tableSeed(std::uint64_t seed, unsigned layer, bool data) {
  SplitMix64 s{seed ^ (0x51ED270B27A1ull * (2 * layer + (data ? 1 : 0) + 1))};
  return s.next();
}

// f(0), ..., f(n - 1), independent tasks: in parallel only when `parallel`.
template <class F>
void runTasks(unsigned n, bool parallel, const F& f) {
  if (!parallel) {
    for (unsigned i = 0; i < n; ++i) f(i);
    return;
  }
  tbb::parallel_for(0u, n, f);
}

}  // namespace

LinklessOctree::LinklessOctree(const OctreeBounds& bounds, const HashedConfig& config, const GeometryMask* geometry)
    : b_(bounds), cfg_(config), geometry_(geometry), rng_{config.seed ^ 0xD1B54A32D192ED03ull} {
  const unsigned layers = b_.depth - b_.start_depth;
  desc_.resize(layers);
  data_.resize(layers);
  edits_.resize(2 * layers);
  build_stats_.resize(layers);
  computeBases();
}

void LinklessOctree::entriesOf(unsigned t, const glm::uvec3& c, const std::uint32_t* set, std::size_t n,
                               const std::vector<gpu::PointLight>& lights, const Reuse* reuse,
                               std::vector<std::uint32_t>& out) const {
  out.resize(n);
  if (!cfg_.octant_masks || t != b_.depth) {
    for (std::size_t i = 0; i < n; ++i) out[i] = packEntry(set[i], kAllOctants);
    return;
  }
  const glm::ivec3 cell(c);
  const GeometryMask::Box* cell_box = nullptr;
  const GeometryMask::OctantBoxes* boxes = geometry_ ? geometry_->octantBoxes(c, cell_box) : nullptr;
  const std::uint32_t *old = reuse ? reuse->first : nullptr, *last = reuse ? reuse->last : nullptr;
  for (std::size_t i = 0; i < n; ++i) {
    const std::uint32_t l = set[i];
    // A set's lights lie anywhere in the light array: asking for the next
    // few ahead overlaps their cache misses (most of this loop's time at 1M lights).
    if (i + kLightPrefetch < n) __builtin_prefetch(&lights[set[i + kLightPrefetch]]);
    while (old != last && entryLight(*old) < l) ++old;
    if (old != last && entryLight(*old) == l) {
      out[i] = *old;  // its mask is up to date (applyOctantRewrites())
      continue;
    }
    const LightOctants octants(lights[l], b_);
    const std::uint8_t m = octants.mask(cell);
    out[i] = packEntry(l, boxes && m ? octants.onGeometry(m, *boxes, *cell_box) : m);
  }
}

void LinklessOctree::buildFrom(const SceneOctree& tree, const std::vector<gpu::PointLight>& lights) {
  const unsigned ds = b_.start_depth, layers = layerCount();
  std::vector<std::vector<DescHash::Entry>> desc_entries(layers);
  std::vector<std::vector<DataHash::Entry>> data_entries(layers);
  std::vector<LeafRef> leaves;
  // A data entry's payload is its leaf's number until the index list is
  // known: the tables depend only on their keys, so they are hashed while
  // the list is made (the deepest data table alone took 60-150 ms on one
  // core at 1M lights, after the list's own serial interning).
  tree.forEachNode([&](unsigned t, const glm::uvec3& c, const SceneOctree::NodeView& v) {
    if (!v.leaf) {
      if (t >= ds && t < b_.depth) desc_entries[t - ds].push_back({c, {v.leaf_mask, v.filled_mask}});
    } else if (!v.lights->empty()) {
      if (t <= ds) throw std::logic_error("scene octree: filled leaf at or above the start depth");
      data_entries[t - ds - 1].push_back({c, {std::uint32_t(leaves.size()), 0}});
      leaves.push_back({t, c, v.lights});
    }
  });
  std::vector<DataTraits::Payload> ranges;
  tbb::parallel_invoke([&] { hashTables(desc_entries, data_entries); },
                       [&] { ranges = internLeaves(leaves, lights); });
  runTasks(layers, true, [&](unsigned i) {
    data_[i].remapPayloads([&](const DataTraits::Payload& leaf) { return ranges[leaf.offset]; });
  });
  edits_.assign(2 * layers, TableEdits{});  // everything, after a build
  computeBases();
  ++layout_version_;
}

std::vector<DataTraits::Payload> LinklessOctree::internLeaves(const std::vector<LeafRef>& leaves,
                                                              const std::vector<gpu::PointLight>& lights) {
  // Each leaf's entries (octant masks) and their hash in parallel, then the
  // sets interned in tree order.
  std::vector<std::vector<std::uint32_t>> entries(leaves.size());
  std::vector<std::uint64_t> hashes(leaves.size());
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, leaves.size(), 256), [&](const auto& r) {
    for (std::size_t j = r.begin(); j != r.end(); ++j) {
      const auto& set = *leaves[j].set;
      entriesOf(leaves[j].t, leaves[j].c, set.data(), set.size(), lights, nullptr, entries[j]);
      if (!ownsRange(leaves[j].t)) hashes[j] = LightSetPool::hashOf(entries[j].data(), entries[j].size());
    }
  });
  pool_.clear();
  std::vector<DataTraits::Payload> ranges(leaves.size());
  for (std::size_t j = 0; j < leaves.size(); ++j) {
    const std::uint32_t offset =
        ownsRange(leaves[j].t) ? pool_.acquireOwn(entries[j]) : pool_.acquire(entries[j], hashes[j]);
    ranges[j] = {offset, std::uint32_t(entries[j].size())};
  }
  return ranges;
}

// buildFrom()'s last step: every layer's two tables, and their build stats.
void LinklessOctree::hashTables(const std::vector<std::vector<DescHash::Entry>>& desc_entries,
                                const std::vector<std::vector<DataHash::Entry>>& data_entries) {
  const unsigned ds = b_.start_depth, layers = layerCount();
  std::vector<PshBuildReport> reports(2 * layers);
  std::size_t keys = 0;
  for (unsigned i = 0; i < layers; ++i) keys += desc_entries[i].size() + data_entries[i].size();
  auto hashTable = [&](unsigned task) {
    const unsigned i = task / 2;
    const bool data = task & 1;
    PshBuildParams p;
    p.seed = tableSeed(cfg_.seed, i, data);
    p.slack = cfg_.table_slack;
    p.sigma = cfg_.table_sigma;
    if (data) data_[i] = DataHash::build(data_entries[i], p, &reports[task]);
    else desc_[i] = DescHash::build(desc_entries[i], p, &reports[task]);
  };
  runTasks(2 * layers, keys >= kParallelHashMinKeys, hashTable);
  for (unsigned i = 0; i < layers; ++i) {
    LayerStats& s = build_stats_[i];
    s = LayerStats{};
    s.depth = ds + i;
    s.desc_attempts = reports[2 * i].attempts;
    s.data_attempts = reports[2 * i + 1].attempts;
    s.rejected_candidates = reports[2 * i].rejected + reports[2 * i + 1].rejected;
    s.hash_ms = reports[2 * i].ms + reports[2 * i + 1].ms;
  }
}

TableEdits LinklessOctree::takeEdits(unsigned layer, bool data) {
  TableEdits& e = edits_[2 * layer + (data ? 1 : 0)];
  TableEdits out = std::move(e);
  e = TableEdits{false, {}, {}};
  return out;
}

void LinklessOctree::computeBases() {
  const unsigned layers = layerCount();
  offset_base_.assign(2 * layers + 1, 0);
  desc_base_.assign(layers + 1, 0);
  data_base_.assign(layers + 1, 0);
  for (unsigned i = 0; i < layers; ++i) {
    offset_base_[2 * i + 1] = offset_base_[2 * i] + desc_[i].offsetCount();
    offset_base_[2 * i + 2] = offset_base_[2 * i + 1] + data_[i].offsetCount();
    desc_base_[i + 1] = desc_base_[i] + desc_[i].slots();
    data_base_[i + 1] = data_base_[i] + data_[i].slots();
  }
}

std::vector<std::uint32_t> LinklessOctree::headerWords() const {
  std::vector<std::uint32_t> h(8 + 16 * layerCount(), 0);
  h[0] = std::bit_cast<std::uint32_t>(b_.origin_f.x);
  h[1] = std::bit_cast<std::uint32_t>(b_.origin_f.y);
  h[2] = std::bit_cast<std::uint32_t>(b_.origin_f.z);
  h[3] = std::bit_cast<std::uint32_t>(b_.cell_scale);
  h[4] = b_.depth;
  h[5] = b_.start_depth;
  h[6] = layerCount();
  auto put = [](std::uint32_t* w, const glm::uvec3& dims, std::size_t base) {
    w[0] = dims.x;
    w[1] = dims.y;
    w[2] = dims.z;
    w[3] = std::uint32_t(base);
  };
  for (unsigned i = 0; i < layerCount(); ++i) {
    std::uint32_t* w = &h[8 + 16 * i];
    put(w, desc_[i].m(), descSlotBase(i));
    put(w + 4, desc_[i].r(), offsetBase(i, false));
    put(w + 8, data_[i].m(), dataSlotBase(i));
    put(w + 12, data_[i].r(), offsetBase(i, true));
  }
  return h;
}

LinklessOctree::GpuImage LinklessOctree::packGpuImage() const {
  GpuImage im;
  im.header = headerWords();
  im.offsets.resize(offsetWordCount());
  im.desc.resize(descSlotCount() * 2);
  im.data.resize(dataSlotCount() * 4);
  for (unsigned i = 0; i < layerCount(); ++i) {
    std::copy(desc_[i].offsetWords().begin(), desc_[i].offsetWords().end(), im.offsets.begin() + offsetBase(i, false));
    std::copy(data_[i].offsetWords().begin(), data_[i].offsetWords().end(), im.offsets.begin() + offsetBase(i, true));
    std::copy(desc_[i].tableWords().begin(), desc_[i].tableWords().end(), im.desc.begin() + descSlotBase(i) * 2);
    std::copy(data_[i].tableWords().begin(), data_[i].tableWords().end(), im.data.begin() + dataSlotBase(i) * 4);
  }
  return im;
}

LinklessOctree::Cell LinklessOctree::cellAt(const glm::vec3& world) const {
  // Mirrors lightListFor() in gl/shaders/hashed/lookup_hashed.glsl.
  const glm::vec3 q = b_.cellCoordF(world);
  const float n = float(1u << b_.depth);
  if (!(q.x >= 0.0f && q.y >= 0.0f && q.z >= 0.0f && q.x < n && q.y < n && q.z < n)) return {};
  const glm::uvec3 cell = glm::min(glm::uvec3(q), glm::uvec3((1u << b_.depth) - 1u));
  Cell at;
  at.kind = Cell::Kind::Empty;
  at.depth = b_.start_depth;
  at.coord = cell >> (b_.depth - b_.start_depth);
  for (unsigned i = 0; i < layerCount(); ++i) {
    const unsigned depth = b_.start_depth + i;
    const glm::uvec3 cur = cell >> (b_.depth - depth);
    const glm::uvec3 nxt = cell >> (b_.depth - depth - 1);
    const auto d = desc_[i].lookup(cur);
    if (!d) return at;  // no node here: no lights
    const glm::uvec3 k = nxt & 1u;
    const unsigned bit = k.x + 2 * k.y + 4 * k.z;
    if ((d->leaf >> bit) & 1u) {
      at.depth = depth + 1;
      at.coord = nxt;
      if ((d->filled >> bit) & 1u) {
        if (const auto r = data_[i].lookup(nxt)) {
          at.kind = Cell::Kind::Filled;
          at.range = {r->offset, r->count, octantOf(q)};
        }
      }
      return at;
    }
  }
  return at;
}

LinklessOctree::Range LinklessOctree::lookup(const glm::vec3& world) const { return cellAt(world).range; }

std::vector<std::uint32_t> LinklessOctree::lightsAt(const glm::vec3& world) const {
  const Range r = lookup(world);
  std::vector<std::uint32_t> out;
  for (std::uint32_t i = r.offset; i < r.offset + r.count; ++i) {
    const std::uint32_t e = pool_.list()[i];
    if ((entryMask(e) >> r.octant) & 1u) out.push_back(entryLight(e));
  }
  return out;
}

// applyTouched() step 1's result for one touched key: what the tables hold
// against what the tree wants, and the entries of a wanted set.
struct LinklessOctree::Derived {
  bool desc_op = false, desc_present = false;
  DescTraits::Payload dp{};
  bool has_data = false, data_want = false;
  std::optional<DataTraits::Payload> data_have;
  std::vector<std::uint32_t> entries;  // wanted, unless in place
  std::uint64_t set_hash = 0;
  bool in_place = false;    // an own range with room for the entries: its words rewritten in step 1
  std::uint32_t count = 0;  // entries, when in place
};

// Per thread of step 1: scratch entries and the list words rewritten in place.
struct LinklessOctree::DeriveScratch {
  std::vector<std::uint32_t> entries;
  std::vector<LightSetPool::Span> rewritten;
};
struct LinklessOctree::ScratchPerThread : tbb::enumerable_thread_specific<DeriveScratch> {};

// Step 2's result: per table, its edits in key order.
struct LinklessOctree::Plan {
  template <class Payload>
  struct Op {
    glm::uvec3 key;
    bool present;
    Payload p;
  };
  std::vector<std::vector<Op<DescTraits::Payload>>> desc_ops;
  std::vector<std::vector<Op<DataTraits::Payload>>> data_ops;
};

void LinklessOctree::applyTouched(const SceneOctree& tree, const std::vector<gpu::PointLight>& lights,
                                  const std::vector<std::uint64_t>& touched, SyncStats& st) {
  const std::vector<Derived> derived = deriveTouched(tree, lights, touched);
  Plan plan = planEdits(touched, derived);
  st.keys += touched.size();
  writeTables(plan, st);
}

// Step 1, per touched key (in parallel for many keys). Reads only, except
// the in-place rewrites of own ranges: they touch only their own range's
// words, so the derive tasks do them (noting the words per thread) instead
// of the sequential step: most deepest leaves end there.
std::vector<LinklessOctree::Derived> LinklessOctree::deriveTouched(const SceneOctree& tree,
                                                                  const std::vector<gpu::PointLight>& lights,
                                                                  const std::vector<std::uint64_t>& touched) {
  const unsigned ds = b_.start_depth;
  std::vector<Derived> derived(touched.size());
  ScratchPerThread scratch;
  auto derive = [&](std::size_t j) {
    const unsigned t = keyDepth(touched[j]);
    const bool has_desc = t >= ds && t < b_.depth, has_data = t > ds && t <= b_.depth;
    if (!has_desc && !has_data) return;
    const glm::uvec3 c = keyCoord(touched[j]);
    Derived& d = derived[j];
    const SceneOctree::NodeView v = tree.find(t, c);
    if (has_desc) {
      const auto have = desc_[t - ds].lookup(c);
      const bool want = v.exists && !v.leaf;
      const DescTraits::Payload p{v.leaf_mask, v.filled_mask};
      if (want != bool(have) || (want && !(*have == p))) {
        d.desc_op = true;
        d.desc_present = want;
        d.dp = p;
      }
    }
    if (has_data) deriveData(t, c, v, lights, d, scratch);
  };
  if (touched.size() < kParallelDeriveMinKeys) {
    for (std::size_t j = 0; j < touched.size(); ++j) derive(j);
  } else {
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, touched.size(), 64), [&](const auto& r) {
      for (std::size_t j = r.begin(); j != r.end(); ++j) derive(j);
    });
  }
  for (const DeriveScratch& sc : scratch)
    for (const auto& span : sc.rewritten) pool_.noteRewritten(span.first, span.end);
  return derived;
}

void LinklessOctree::deriveData(unsigned t, const glm::uvec3& c, const SceneOctree::NodeView& v,
                                const std::vector<gpu::PointLight>& lights, Derived& d, ScratchPerThread& sc) {
  d.has_data = true;
  d.data_have = data_[t - b_.start_depth - 1].lookup(c);
  d.data_want = v.exists && v.leaf && !v.lights->empty();
  if (!d.data_want) return;
  // An own range that exists already lends its words and, with room for
  // the set, takes the new ones in place.
  const bool own = ownsRange(t);
  const std::vector<std::uint32_t>& set = *v.lights;
  std::optional<Reuse> reuse;
  if (own && d.data_have)
    reuse = Reuse{pool_.list().data() + d.data_have->offset,
                  pool_.list().data() + d.data_have->offset + d.data_have->count};
  if (reuse && set.size() <= pool_.capacityOf(d.data_have->offset)) {
    rewriteInPlace(t, c, set, *d.data_have, lights, sc.local());
    d.in_place = true;
    d.count = std::uint32_t(set.size());
    return;
  }
  entriesOf(t, c, set.data(), set.size(), lights, reuse ? &*reuse : nullptr, d.entries);
  if (!own) d.set_hash = LightSetPool::hashOf(d.entries.data(), d.entries.size());
}

void LinklessOctree::rewriteInPlace(unsigned t, const glm::uvec3& c, const std::vector<std::uint32_t>& set,
                                    const DataTraits::Payload& have, const std::vector<gpu::PointLight>& lights,
                                    DeriveScratch& sc) {
  const std::uint32_t offset = have.offset;
  std::uint32_t* words = pool_.ownWords(offset);
  // The lights before the first change keep their words (their masks are
  // current: applyOctantRewrites()); the rest are merged.
  std::uint32_t p = 0;
  const std::uint32_t common = std::min(std::uint32_t(set.size()), have.count);
  while (p < common && entryLight(words[p]) == set[p]) ++p;
  const Reuse rest{words + p, words + have.count};
  entriesOf(t, c, set.data() + p, set.size() - p, lights, &rest, sc.entries);
  std::uint32_t first = ~0u, last = 0;
  for (std::uint32_t k = 0; k < sc.entries.size(); ++k)
    if (words[p + k] != sc.entries[k]) {
      words[p + k] = sc.entries[k];
      first = std::min(first, p + k);
      last = p + k;
    }
  if (first != ~0u) sc.rewritten.push_back({offset + first, offset + last + 1});
  if (set.size() != have.count) {
    const std::uint32_t head = pool_.resizeOwn(offset, std::uint32_t(set.size()));
    sc.rewritten.push_back({head, head + 1});
  }
}

// Step 2, sequentially in key order: interning the wanted sets (so that
// offsets do not depend on threads), and the edit lists per table.
LinklessOctree::Plan LinklessOctree::planEdits(const std::vector<std::uint64_t>& touched,
                                               const std::vector<Derived>& derived) {
  const unsigned ds = b_.start_depth;
  Plan plan;
  plan.desc_ops.resize(layerCount());
  plan.data_ops.resize(layerCount());
  std::vector<std::uint32_t> release;
  for (std::size_t j = 0; j < touched.size(); ++j) {
    const Derived& d = derived[j];
    const unsigned t = keyDepth(touched[j]);
    const glm::uvec3 c = keyCoord(touched[j]);
    if (d.desc_op) plan.desc_ops[t - ds].push_back({c, d.desc_present, d.dp});
    if (!d.has_data) continue;
    auto& ops = plan.data_ops[t - ds - 1];
    const auto& have = d.data_have;
    if (d.in_place) {
      if (d.count != have->count) ops.push_back({c, true, {have->offset, d.count}});  // resized in step 1
    } else if (d.data_want) {
      const std::uint32_t offset = ownsRange(t) ? pool_.acquireOwn(d.entries) : pool_.acquire(d.entries, d.set_hash);
      const DataTraits::Payload p{offset, std::uint32_t(d.entries.size())};
      if (have && *have == p) {
        pool_.release(p.offset);
      } else {
        ops.push_back({c, true, p});
        if (have) release.push_back(have->offset);
      }
    } else if (have) {
      ops.push_back({c, false, {}});
      release.push_back(have->offset);
    }
  }
  for (const auto off : release) pool_.release(off);
  return plan;
}

// One table's edits: erases first (their slots may take the inserts), then
// updates and inserts; the thesis's criterion, a new key that collides even
// after re-offsetting its group, rebuilds the table. The slots and offsets
// written are noted for the partial upload. True if the table's size (and
// so the GPU layout) changed.
template <class Hash, class Ops>
bool LinklessOctree::editTable(Hash& table, const Ops& ops, unsigned task, SplitMix64& rng, SyncStats& ts) {
  TableEdits& edits = edits_[task];
  for (const auto& op : ops)
    if (!op.present) {
      if (table.erase(op.key)) edits.slot(table.slot(op.key));
      ++ts.erases;
    }
  std::vector<typename Hash::Entry> failed;
  std::vector<std::uint32_t> group;  // an insert's offset group before it
  for (const auto& op : ops) {
    if (!op.present) continue;
    if (table.update(op.key, op.p)) {
      edits.slot(table.slot(op.key));
      ++ts.updates;
      continue;
    }
    ++ts.inserts;
    if (!failed.empty()) {
      failed.push_back({op.key, op.p});
      continue;
    }
    table.trackGroups();
    group = table.groupSlots(op.key);
    switch (table.insert(op.key, op.p, rng)) {
      case Hash::InsertResult::InPlace:
        edits.slot(table.slot(op.key));
        ++ts.in_place;
        break;
      case Hash::InsertResult::Reoffset:
        for (const auto s : group) edits.slot(s);
        for (const auto s : table.groupSlots(op.key)) edits.slot(s);
        edits.offset(table.offsetIndex(op.key));
        ++ts.reoffsets;
        break;
      case Hash::InsertResult::Failed: failed.push_back({op.key, op.p}); break;
    }
  }
  if (failed.empty()) return false;
  auto all = table.entries();
  all.insert(all.end(), failed.begin(), failed.end());
  PshBuildParams p;
  p.slack = cfg_.rehash_slack;
  p.sigma = cfg_.rehash_sigma;
  p.seed = tableSeed(cfg_.seed, task / 2, task & 1) ^ rng.next();
  const std::size_t old_slots = table.slots(), old_offsets = table.offsetCount();
  table = Hash::build(all, p);
  edits.markAll();
  ++ts.rehashed_tables;
  return table.slots() != old_slots || table.offsetCount() != old_offsets;
}

// Step 3, the table writes: tables are independent, so each is edited by
// its own task with its own random stream (drawn here, in table order).
void LinklessOctree::writeTables(const Plan& plan, SyncStats& st) {
  const unsigned layers = layerCount();
  std::vector<SyncStats> task_stats(2 * layers);
  std::vector<std::uint8_t> task_layout(2 * layers, 0);
  std::vector<std::uint64_t> task_seed(2 * layers);
  std::size_t ops_total = 0;
  for (unsigned i = 0; i < layers; ++i) ops_total += plan.desc_ops[i].size() + plan.data_ops[i].size();
  for (auto& sd : task_seed) sd = rng_.next();
  auto applyTask = [&](unsigned task) {
    const unsigned i = task / 2;
    const bool data = task & 1;
    if (data ? plan.data_ops[i].empty() : plan.desc_ops[i].empty()) return;
    SplitMix64 rng{task_seed[task]};
    task_layout[task] = data ? editTable(data_[i], plan.data_ops[i], task, rng, task_stats[task])
                             : editTable(desc_[i], plan.desc_ops[i], task, rng, task_stats[task]);
  };
  runTasks(2 * layers, ops_total >= kParallelTableEditsMinOps, applyTask);
  bool layout_changed = false;
  for (unsigned task = 0; task < 2 * layers; ++task) {
    const SyncStats& ts = task_stats[task];
    st.inserts += ts.inserts;
    st.updates += ts.updates;
    st.erases += ts.erases;
    st.in_place += ts.in_place;
    st.reoffsets += ts.reoffsets;
    st.rehashed_tables += ts.rehashed_tables;
    layout_changed |= task_layout[task] != 0;
  }
  if (layout_changed) {
    computeBases();
    ++layout_version_;
  }
}

std::vector<OctantRewrite> LinklessOctree::findOctantRewrites(std::vector<OctantChange>& changes) const {
  std::vector<OctantRewrite> out;
  if (!cfg_.octant_masks) return out;
  // Grouped by cell (lights ascending within a cell: the sort is stable), so
  // that each cell is looked up once and its range walked once.
  std::vector<OctantChange> scratch;
  sortByKeyStable(changes, scratch);
  const DataHash& data = data_[b_.depth - b_.start_depth - 1];
  const auto& list = pool_.list();
  // Per batch of cells: every slot, then every range, prefetched before
  // they are read (two cache misses per cell otherwise, most of the time).
  constexpr std::size_t kBatch = 128;
  std::uint32_t first[kBatch + 1], slot[kBatch];
  std::optional<DataTraits::Payload> range[kBatch];
  for (std::size_t i = 0; i < changes.size();) {
    std::size_t n = 0;
    for (; n < kBatch && i < changes.size(); ++n) {
      first[n] = std::uint32_t(i);
      slot[n] = data.slot(keyCoord(changes[i].key));
      data.prefetchSlot(slot[n]);
      const std::uint64_t key = changes[i].key;
      while (++i < changes.size() && changes[i].key == key) {
      }
    }
    first[n] = std::uint32_t(i);
    for (std::size_t g = 0; g < n; ++g) {
      range[g] = data.lookupAt(slot[g], keyCoord(changes[first[g]].key));
      if (!range[g]) continue;
      const std::uint32_t* w = list.data() + range[g]->offset;
      for (std::uint32_t k = 0; k < range[g]->count; k += 16) __builtin_prefetch(w + k);
    }
    for (std::size_t g = 0; g < n; ++g) {
      const auto& r = range[g];
      if (!r) continue;  // not a filled deepest leaf
      const std::uint32_t *e = list.data() + r->offset, *last = e + r->count;
      for (std::size_t k = first[g]; k < first[g + 1]; ++k) {
        const OctantChange& ch = changes[k];
        // Branch-free lower bound within the rest of the range (tens of lights).
        for (std::size_t len = std::size_t(last - e); len > 1;) {
          const std::size_t half = len / 2;
          e = entryLight(e[half - 1]) < ch.light ? e + half : e;
          len -= half;
        }
        if (e != last && entryLight(*e) < ch.light) ++e;
        if (e == last) break;
        if (entryLight(*e) != ch.light) continue;  // not listed here
        const std::uint32_t w = packEntry(ch.light, ch.mask);
        if (w != *e) out.push_back({ch.key, std::uint32_t(e - list.data()), w});
      }
    }
  }
  return out;
}

void LinklessOctree::applyOctantRewrites(const std::vector<OctantRewrite>& rewrites) {
  for (const OctantRewrite& rw : rewrites) pool_.rewrite(rw.at, rw.word);
}

bool LinklessOctree::compactIfWanted() {
  if (!pool_.wantsCompaction()) return false;
  const auto& remap = pool_.compact();
  auto remapLayer = [&](unsigned i) {
    data_[i].remapPayloads([&](const DataTraits::Payload& p) { return DataTraits::Payload{remap[p.offset], p.count}; });
  };
  runTasks(layerCount(), pool_.list().size() >= kParallelRemapMinEntries, remapLayer);
  for (unsigned i = 0; i < layerCount(); ++i) edits_[2 * i + 1].markAll();
  return true;
}

std::vector<LayerStats> LinklessOctree::layerStats() const {
  std::vector<LayerStats> out = build_stats_;
  for (unsigned i = 0; i < layerCount(); ++i) {
    LayerStats& s = out[i];
    s.depth = b_.start_depth + i;
    s.desc_keys = desc_[i].size();
    s.data_keys = data_[i].size();
    s.desc_slots = desc_[i].slots();
    s.data_slots = data_[i].slots();
    s.desc_offsets = desc_[i].offsetCount();
    s.data_offsets = data_[i].offsetCount();
    s.bytes = desc_[i].bytes() + data_[i].bytes();
  }
  return out;
}

std::size_t LinklessOctree::tableBytes() const {
  std::size_t s = 0;
  for (unsigned i = 0; i < layerCount(); ++i) s += desc_[i].bytes() + data_[i].bytes();
  return s;
}

std::size_t LinklessOctree::gpuBytes() const {
  return tableBytes() + (8 + 16 * layerCount()) * 4 + pool_.list().size() * 4;
}

}  // namespace ml::hashed
