// SceneOctree::replaceAll(): many lights' edits at once, one task per
// subtree at depth min(2, start depth), on node blocks reserved beforehand
// so that the node arrays stay put. Contract: SceneOctree.hpp.
#include <tbb/parallel_for.h>

#include <algorithm>
#include <stdexcept>

#include "host/hashed/SceneOctree.hpp"

namespace ml::hashed {

std::vector<std::int32_t> SceneOctree::openTop(unsigned P) {
  // Every node above depth P becomes a branch (the tasks must not split
  // shared nodes); normalize() merges back the ones that stay empty.
  std::vector<std::int32_t> part(std::size_t(1) << (3 * P), -1);  // depth-P node per subtree
  auto open = [&](auto& self, std::int32_t n, unsigned t, const glm::uvec3& c, std::size_t id) -> void {
    if (t == P) {
      part[id] = n;
      return;
    }
    if (!care(t, c)) return;  // nothing is ever stored below
    nodes_[n].dirty = true;
    if (isLeaf(n)) split(main_, n, t, c);
    for (unsigned k = 0; k < 8; ++k) self(self, nodes_[n].child + std::int32_t(k), t + 1, childCoord(c, k), id * 8 + k);
  };
  open(open, 0, 0, glm::uvec3(0), 0);
  return part;
}

std::size_t SceneOctree::partId(const glm::uvec3& c, unsigned P) {  // depth-P coordinate -> index in openTop()
  std::size_t id = 0;
  for (unsigned d = 0; d < P; ++d) id = id * 8 + childBit(c >> (P - d - 1));
  return id;
}

void SceneOctree::route(const std::vector<std::int32_t>& part, const std::vector<std::size_t>& ids, std::uint32_t item,
                        std::vector<std::uint8_t>& seen, std::vector<std::vector<std::uint32_t>>& work) {
  for (const auto id : ids)
    if (part[id] >= 0 && !seen[id]) {
      seen[id] = 1;
      work[id].push_back(item);
    }
  for (const auto id : ids) seen[id] = 0;
}

void SceneOctree::reserveBlocks(std::size_t bound) {
  if (free_blocks_.size() < bound) {
    const std::size_t grow = bound - free_blocks_.size();
    const std::int32_t first = std::int32_t(nodes_.size());
    nodes_.resize(nodes_.size() + 8 * grow);
    sets_.resize(sets_.size() + 8 * grow);
    sums_.resize(sums_.size() + 8 * grow);
    for (std::size_t i = grow; i-- > 0;) free_blocks_.push_back(first + std::int32_t(8 * i));
  }
  reserved_taken_.store(0, std::memory_order_relaxed);
}

template <class Edit>
void SceneOctree::runLanes(unsigned P, const std::vector<std::int32_t>& part,
                           const std::vector<std::vector<std::uint32_t>>& work, Edit&& edit) {
  std::vector<std::size_t> busy;
  for (std::size_t id = 0; id < part.size(); ++id)
    if (!work[id].empty()) busy.push_back(id);
  std::vector<Lane> lanes(busy.size());
  std::vector<std::size_t> done(busy.size(), 0);  // per lane: items edited
  auto coordOf = [&](std::size_t id) {
    glm::uvec3 c(0);
    for (unsigned d = 0; d < P; ++d) c = childCoord(c, unsigned(id >> (3 * (P - d - 1))) & 7u);
    return c;
  };
  tbb::parallel_for(std::size_t(0), busy.size(), [&](std::size_t i) {
    const std::size_t id = busy[i];
    Lane& ln = lanes[i];
    ln.reserved = true;
    const glm::uvec3 c = coordOf(id);
    for (const auto j : work[id]) {
      if (!edit(ln, part[id], c, j)) return;
      ++done[i];
    }
    // The subtree is final: merge what became mergeable while it is in
    // cache, in parallel; normalize() then finds it clean.
    normalizeRec(ln, part[id], P, c);
  });
  free_blocks_.resize(free_blocks_.size() - reserved_taken_.load(std::memory_order_relaxed));
  for (auto& ln : lanes) {
    free_blocks_.insert(free_blocks_.end(), ln.freed.begin(), ln.freed.end());
    if (recording_) main_.touched.insert(main_.touched.end(), ln.touched.begin(), ln.touched.end());
  }
  // The items the reservation did not cover, in order, on the main lane.
  for (std::size_t i = 0; i < busy.size(); ++i)
    for (std::size_t k = done[i]; k < work[busy[i]].size(); ++k)
      edit(main_, part[busy[i]], coordOf(busy[i]), work[busy[i]][k]);
}

bool SceneOctree::claimBlocks(std::size_t n) {
  std::ptrdiff_t b = budget_.load(std::memory_order_relaxed);
  while (b >= std::ptrdiff_t(n))
    if (budget_.compare_exchange_weak(b, b - std::ptrdiff_t(n), std::memory_order_relaxed)) return true;
  return false;
}

// The blocks a light's new version may split in subtree `sub` (depth P):
// at most every node at depths P .. depth - 1 of the subtree that its cell
// box reaches (a partly covered leaf, or a full one at or above the start
// depth; each node splits once).
std::size_t SceneOctree::worstSplits(const LightCells* v, unsigned P, const glm::uvec3& sub) const {
  if (!v || v->box().empty()) return 0;
  const unsigned below = b_.depth - P;
  const glm::ivec3 slo(glm::ivec3(sub) << int(below)), shi = slo + ((1 << int(below)) - 1);
  const glm::ivec3 lo = glm::max(v->box().lo, slo), hi = glm::min(v->box().hi, shi);
  if (lo.x > hi.x || lo.y > hi.y || lo.z > hi.z) return 0;
  std::size_t bound = 0;
  for (unsigned t = P; t < b_.depth; ++t) {
    const glm::ivec3 n = (hi >> int(b_.depth - t)) - (lo >> int(b_.depth - t)) + 1;
    bound += std::size_t(n.x) * std::size_t(n.y) * std::size_t(n.z);
  }
  return bound;
}

// Each light's work item goes to the subtrees its versions' cell boxes reach, in batch order.
std::vector<std::vector<std::uint32_t>> SceneOctree::routeCells(const std::vector<CellsReplacement>& batch,
                                                                const std::vector<std::int32_t>& part,
                                                                unsigned P) const {
  const unsigned below = b_.depth - P;
  std::vector<std::vector<std::uint32_t>> work(part.size());
  std::vector<std::uint8_t> seen(part.size(), 0);
  std::vector<std::size_t> ids;
  for (std::uint32_t j = 0; j < batch.size(); ++j) {
    ids.clear();
    for (const LightCells* v : {batch[j].old_version, batch[j].new_version}) {
      if (!v || v->box().empty()) continue;
      const glm::ivec3 lo = v->box().lo >> int(below), hi = v->box().hi >> int(below);
      for (int z = lo.z; z <= hi.z; ++z)
        for (int y = lo.y; y <= hi.y; ++y)
          for (int x = lo.x; x <= hi.x; ++x) ids.push_back(partId(glm::uvec3(glm::ivec3(x, y, z)), P));
    }
    route(part, ids, j, seen, work);
  }
  return work;
}

void SceneOctree::replaceAll(const std::vector<CellsReplacement>& batch) {
  static const LightCells kNone;
  const unsigned P = std::min(2u, b_.start_depth);
  if (P == 0 || batch.size() < kParallelEditMinLights) {
    for (const auto& r : batch)
      replace(r.old_version ? *r.old_version : kNone, r.new_version ? *r.new_version : kNone, r.light);
    return;
  }
  const std::vector<std::int32_t> part = openTop(P);
  const auto work = routeCells(batch, part, P);
  // worstSplits() is far above the splits that happen, so instead of
  // reserving its sum each lane claims a light's bound from a shared budget
  // before editing it and returns what it did not take; a light whose bound
  // no longer fits waits for the sequential pass. Free blocks are kept
  // between updates (normalize() frees merged ones), so this grows the
  // arrays once.
  reserveBlocks(std::max<std::size_t>(free_blocks_.size(), kReservedBlocks));
  budget_.store(std::ptrdiff_t(free_blocks_.size()), std::memory_order_relaxed);
  runLanes(P, part, work, [&](Lane& ln, std::int32_t n, const glm::uvec3& c, std::uint32_t j) {
    const LightCells& a = batch[j].old_version ? *batch[j].old_version : kNone;
    const LightCells& b = batch[j].new_version ? *batch[j].new_version : kNone;
    // (A default LightCells may only be asked at the root.)
    const LightNode ka = batch[j].old_version ? a.cover(P, c) : LightNode::Empty;
    const LightNode kb = batch[j].new_version ? b.cover(P, c) : LightNode::Empty;
    if (ka == kb && ka != LightNode::Branch) return true;  // unchanged here
    std::size_t claimed = 0;
    if (ln.reserved) {
      claimed = worstSplits(batch[j].new_version, P, c);
      if (!claimBlocks(claimed)) return false;
    }
    const std::size_t taken = ln.taken;
    replaceCellsRec(ln, n, P, c, ka, a, kb, b, batch[j].light);
    if (ln.reserved) returnBlocks(claimed - (ln.taken - taken));
    return true;
  });
}

}  // namespace ml::hashed
