#include "host/hashed/SceneOctree.hpp"

#include <algorithm>
#include <stdexcept>

#include "host/hashed/KeySort.hpp"
#include "host/hashed/LightSetPool.hpp"

namespace ml::hashed {
namespace {

void skipChildren(const LightNode*& cur) {
  for (int k = 0; k < 8; ++k) skipLightSubtree(cur);
}

const std::vector<std::uint32_t> kNoLights;

}  // namespace

SceneOctree::SceneOctree(const OctreeBounds& bounds, const GeometryMask* mask) : b_(bounds), mask_(mask) {
  nodes_.emplace_back();
  sets_.emplace_back();
  sums_.push_back(0);
}

void SceneOctree::record(Lane& ln, std::int32_t n, unsigned t, const glm::uvec3& c) {
  if (!recording_) return;
  ln.touched.push_back(nodeKey(t, c));
  // The parent's description (its children's leaf/filled bits) changes only
  // when the leaf's set became or stopped being empty; a set of one or none
  // covers both. Most edits leave a set non-empty, and most touched keys
  // would otherwise be such parents, looked up for nothing.
  if (t > 0 && sets_[n].size() <= 1) recordParent(ln, nodeKey(t - 1, c >> 1u));
}

void SceneOctree::recordChildren(Lane& ln, unsigned t, const glm::uvec3& c) {
  if (!recording_) return;
  ln.touched.push_back(nodeKey(t, c));
  if (t > 0) recordParent(ln, nodeKey(t - 1, c >> 1u));
  for (unsigned k = 0; k < 8; ++k) ln.touched.push_back(nodeKey(t + 1, childCoord(c, k)));
}

std::vector<std::uint64_t> SceneOctree::takeTouched() {
  std::vector<std::uint64_t> out;
  out.swap(main_.touched);
  main_.last_parent = ~std::uint64_t(0);
  sortUniqueKeys(out, sort_scratch_);
  return out;
}

std::int32_t SceneOctree::allocBlock(Lane& ln) {
  if (ln.reserved) {
    // Parallel edits take the blocks reserved beforehand (nodes_ must not grow).
    const std::size_t i = reserved_taken_.fetch_add(1, std::memory_order_relaxed);
    if (i >= free_blocks_.size()) throw std::logic_error("scene octree: parallel edits outgrew their reservation");
    ++ln.taken;
    return free_blocks_[free_blocks_.size() - 1 - i];
  }
  if (!free_blocks_.empty()) {
    const std::int32_t b = free_blocks_.back();
    free_blocks_.pop_back();
    return b;
  }
  const std::int32_t b = std::int32_t(nodes_.size());
  nodes_.resize(nodes_.size() + 8);
  sets_.resize(sets_.size() + 8);
  sums_.resize(sums_.size() + 8);
  return b;
}

// Table 7.1, "leaf meets branch": the leaf becomes a branch whose children
// carry its lights (children without geometry stay empty: nothing queries them).
void SceneOctree::split(Lane& ln, std::int32_t n, unsigned t, const glm::uvec3& c) {
  const std::int32_t block = allocBlock(ln);
  for (unsigned k = 0; k < 8; ++k) {
    const std::int32_t ch = block + std::int32_t(k);
    nodes_[ch] = Node{};
    nodes_[ch].dirty = true;
    if (care(t + 1, childCoord(c, k))) {
      sets_[ch] = sets_[n];
      sums_[ch] = sums_[n];
    } else {
      sets_[ch].clear();
      sums_[ch] = 0;
    }
  }
  nodes_[n].child = block;
  std::vector<std::uint32_t>().swap(sets_[n]);
  sums_[n] = 0;
  recordChildren(ln, t, c);
}

bool SceneOctree::addToSet(std::int32_t n, std::uint32_t l) {
  auto& s = sets_[n];
  if (s.empty() || s.back() < l) {
    s.push_back(l);  // full builds insert lights in index order
  } else {
    const auto it = std::lower_bound(s.begin(), s.end(), l);
    if (it != s.end() && *it == l) return false;
    s.insert(it, l);
  }
  sums_[n] += LightSetPool::elementHash(l);
  return true;
}

bool SceneOctree::eraseFromSet(std::int32_t n, std::uint32_t l) {
  auto& s = sets_[n];
  const auto it = std::lower_bound(s.begin(), s.end(), l);
  if (it == s.end() || *it != l) return false;
  s.erase(it);
  sums_[n] -= LightSetPool::elementHash(l);
  return true;
}

void SceneOctree::insert(const LightOctree& lo) {
  for (unsigned r = 0; r < lo.root_count; ++r) {
    std::int32_t n = 0;
    unsigned t = 0;
    glm::uvec3 c(0);
    bool stored = true;
    // Descend to the root, splitting leaves on the way.
    while (t < lo.root_depth) {
      if (!care(t, c)) {
        stored = false;
        break;
      }
      nodes_[n].dirty = true;
      if (isLeaf(n)) split(main_, n, t, c);
      const glm::uvec3 cc = lo.roots[r] >> (lo.root_depth - t - 1);
      n = nodes_[n].child + std::int32_t(childBit(cc));
      ++t;
      c = cc;
    }
    if (!stored) continue;
    const LightNode* cur = lo.nodes.data() + lo.root_start[r];
    insertRec(n, t, c, cur, lo.light);
  }
}

void SceneOctree::insertRec(std::int32_t n, unsigned t, const glm::uvec3& c, const LightNode*& cur,
                            std::uint32_t l) {
  const LightNode type = *cur++;
  if (type == LightNode::Empty) return;  // Table 7.1: "stop"
  if (!care(t, c)) {
    if (type == LightNode::Branch) skipChildren(cur);
    return;
  }
  if (type == LightNode::Full) {
    addFull(main_, n, t, c, l);
    return;
  }
  nodes_[n].dirty = true;
  if (isLeaf(n)) split(main_, n, t, c);
  const std::int32_t ch = nodes_[n].child;
  for (unsigned k = 0; k < 8; ++k) insertRec(ch + std::int32_t(k), t + 1, childCoord(c, k), cur, l);
}

// Table 7.1, full light node: added to a leaf, or to every child of a branch.
void SceneOctree::addFull(Lane& ln, std::int32_t n, unsigned t, const glm::uvec3& c, std::uint32_t l) {
  if (!care(t, c)) return;
  nodes_[n].dirty = true;
  if (isLeaf(n)) {
    if (t > b_.start_depth) {
      if (addToSet(n, l)) record(ln, n, t, c);
      return;
    }
    split(ln, n, t, c);  // no non-empty leaves at or above the start depth
  }
  const std::int32_t ch = nodes_[n].child;
  for (unsigned k = 0; k < 8; ++k) addFull(ln, ch + std::int32_t(k), t + 1, childCoord(c, k), l);
}

void SceneOctree::remove(const LightOctree& lo) {
  for (unsigned r = 0; r < lo.root_count; ++r) {
    std::int32_t n = 0;
    unsigned t = 0;
    glm::uvec3 c(0);
    bool below = true;
    while (t < lo.root_depth) {
      if (!care(t, c)) {
        below = false;
        break;
      }
      if (isLeaf(n)) {
        if (eraseFromSet(n, lo.light)) {
          nodes_[n].dirty = true;
          record(main_, n, t, c);
        }
        below = false;
        break;
      }
      nodes_[n].dirty = true;
      const glm::uvec3 cc = lo.roots[r] >> (lo.root_depth - t - 1);
      n = nodes_[n].child + std::int32_t(childBit(cc));
      ++t;
      c = cc;
    }
    if (!below) continue;
    const LightNode* cur = lo.nodes.data() + lo.root_start[r];
    removeRec(n, t, c, cur, lo.light);
  }
}

// Table 8.2: remove the index where the light's octree is non-empty; a leaf
// holds the light for all of its cells or for none, so leaves need no split.
void SceneOctree::removeRec(std::int32_t n, unsigned t, const glm::uvec3& c, const LightNode*& cur,
                            std::uint32_t l) {
  const LightNode type = *cur++;
  if (type == LightNode::Empty) return;
  if (!care(t, c)) {
    if (type == LightNode::Branch) skipChildren(cur);
    return;
  }
  if (isLeaf(n)) {
    if (eraseFromSet(n, l)) {
      nodes_[n].dirty = true;
      record(main_, n, t, c);
    }
    if (type == LightNode::Branch) skipChildren(cur);
    return;
  }
  nodes_[n].dirty = true;
  if (type == LightNode::Full) {
    removeAll(main_, n, t, c, l);
    return;
  }
  const std::int32_t ch = nodes_[n].child;
  for (unsigned k = 0; k < 8; ++k) removeRec(ch + std::int32_t(k), t + 1, childCoord(c, k), cur, l);
}

void SceneOctree::removeAll(Lane& ln, std::int32_t n, unsigned t, const glm::uvec3& c, std::uint32_t l) {
  if (isLeaf(n)) {
    if (eraseFromSet(n, l)) {
      nodes_[n].dirty = true;
      record(ln, n, t, c);
    }
    return;
  }
  nodes_[n].dirty = true;
  const std::int32_t ch = nodes_[n].child;
  for (unsigned k = 0; k < 8; ++k) removeAll(ln, ch + std::int32_t(k), t + 1, childCoord(c, k), l);
}

void SceneOctree::normalize() {
  normalizeRec(main_, 0, 0, glm::uvec3(0));
  free_blocks_.insert(free_blocks_.end(), main_.freed.begin(), main_.freed.end());
  main_.freed.clear();
}

void SceneOctree::normalizeRec(Lane& ln, std::int32_t n, unsigned t, const glm::uvec3& c) {
  if (!nodes_[n].dirty) return;
  nodes_[n].dirty = false;
  if (isLeaf(n)) return;
  const std::int32_t ch = nodes_[n].child;
  for (unsigned k = 0; k < 8; ++k) normalizeRec(ln, ch + std::int32_t(k), t + 1, childCoord(c, k));
  // Merge when the children that matter are leaves with one light set.
  const std::vector<std::uint32_t>* common = nullptr;
  for (unsigned k = 0; k < 8; ++k) {
    const std::int32_t x = ch + std::int32_t(k);
    if (!care(t + 1, childCoord(c, k))) continue;  // an empty leaf that takes any set
    if (!isLeaf(x)) return;
    if (!common) common = &sets_[x];
    else if (sums_[common - sets_.data()] != sums_[x] || *common != sets_[x]) return;
  }
  const bool empty = !common || common->empty();
  if (!empty && t <= b_.start_depth) return;
  if (!empty) {
    sets_[n] = *common;
    sums_[n] = sums_[common - sets_.data()];
  } else {
    sets_[n].clear();
    sums_[n] = 0;
  }
  for (unsigned k = 0; k < 8; ++k) {
    std::vector<std::uint32_t>().swap(sets_[ch + std::int32_t(k)]);
    sums_[ch + std::int32_t(k)] = 0;
  }
  nodes_[n].child = -1;
  ln.freed.push_back(ch);
  recordChildren(ln, t, c);
}

SceneOctree::NodeView SceneOctree::view(std::int32_t n) const {
  NodeView v;
  v.exists = true;
  v.leaf = isLeaf(n);
  if (v.leaf) {
    v.lights = &sets_[n];
    v.set_sum = sums_[n];
    return v;
  }
  for (unsigned k = 0; k < 8; ++k) {
    const std::int32_t x = nodes_[n].child + std::int32_t(k);
    if (isLeaf(x)) {
      v.leaf_mask |= std::uint8_t(1u << k);
      if (!sets_[x].empty()) v.filled_mask |= std::uint8_t(1u << k);
    }
  }
  return v;
}

SceneOctree::NodeView SceneOctree::find(unsigned depth, const glm::uvec3& coord) const {
  std::int32_t n = 0;
  for (unsigned t = 0; t < depth; ++t) {
    if (isLeaf(n)) return {};
    const glm::uvec3 cc = coord >> (depth - t - 1);
    n = nodes_[n].child + std::int32_t(childBit(cc));
  }
  return view(n);
}

const std::vector<std::uint32_t>& SceneOctree::lightsAtCell(const glm::uvec3& c) const {
  std::int32_t n = 0;
  for (unsigned t = 0; t < b_.depth && !isLeaf(n); ++t) {
    const glm::uvec3 cc = c >> (b_.depth - t - 1);
    n = nodes_[n].child + std::int32_t(childBit(cc));
  }
  return isLeaf(n) ? sets_[n] : kNoLights;
}

std::vector<SceneOctree::LayerCounts> SceneOctree::countsPerDepth() const {
  std::vector<LayerCounts> out(b_.depth + 1);
  forEachNode([&](unsigned t, const glm::uvec3&, const NodeView& v) {
    if (!v.leaf) ++out[t].branches;
    else if (v.lights->empty()) ++out[t].empty_leaves;
    else ++out[t].filled_leaves;
  });
  return out;
}

std::size_t SceneOctree::indexEntries() const {
  std::size_t s = 0;
  forEachNode([&](unsigned, const glm::uvec3&, const NodeView& v) {
    if (v.leaf) s += v.lights->size();
  });
  return s;
}

}  // namespace ml::hashed
