#pragma once
// The scene octree: per leaf the sorted indices of the lights overlapping it
// (thesis §7.2.4), built by merging light octrees top-down per Table 7.1 and
// edited by removing them again (Table 8.2). Contract:
//  - Canonical form after normalize(): a node is a leaf iff every cell below
//    it that "matters" holds the same light set; with a geometry mask only
//    cells containing geometry matter (the relaxed merge rule, future work
//    A), and subtrees without geometry are empty leaves. Without a mask every
//    cell matters. Nodes at depth <= start_depth are never non-empty leaves
//    (the linkless octree stores depth start_depth + 1 and deeper leaves).
//    The canonical form depends only on the light set, not on the order of
//    insertions and removals: that is what makes incremental updates equal
//    to a fresh build.
//  - insert()/remove() leave the tree valid (every leaf's set is exactly the
//    lights covering its cells) but maybe not minimal; normalize() merges
//    the subtrees they touched.
//  - With recording on, every node whose type or set changed and every node
//    created or freed are reported by takeTouched(), with the parents whose
//    description (children's leaf / filled bits) may have changed: of a
//    node created, freed or split, or of a leaf whose set became or stopped
//    being empty. These are the keys whose hash entries the linkless octree
//    must re-derive.
#include <glm/glm.hpp>

#include <algorithm>
#include <cstdint>
#include <vector>

#include "host/hashed/GeometryMask.hpp"
#include "host/hashed/LightSetPool.hpp"
#include "host/hashed/LightOctreeBuilder.hpp"
#include "host/hashed/OctreeBounds.hpp"

namespace ml::hashed {

// Depth in bits 48..51, coordinates in 16 bits each below.
inline std::uint64_t nodeKey(unsigned depth, const glm::uvec3& c) {
  return (std::uint64_t(depth) << 48) | packCoord(c);
}
inline unsigned keyDepth(std::uint64_t k) { return unsigned(k >> 48); }
inline glm::uvec3 keyCoord(std::uint64_t k) { return unpackCoord(k & 0xFFFFFFFFFFFFull); }
inline glm::uvec3 childCoord(const glm::uvec3& c, unsigned k) {
  return c * 2u + glm::uvec3(k & 1u, (k >> 1) & 1u, (k >> 2) & 1u);
}
// The inverse: which child of its parent node `child` is.
inline unsigned childBit(const glm::uvec3& child) {
  return (child.x & 1u) | ((child.y & 1u) << 1) | ((child.z & 1u) << 2);
}

class SceneOctree {
 public:
  SceneOctree(const OctreeBounds& bounds, const GeometryMask* mask);

  void insert(const LightOctree& light);
  void remove(const LightOctree& light);
  // A light's new version replacing its old one (same index): walks both
  // octrees together and touches only the nodes whose coverage differs
  // (the additions and removals per node of the thesis's future-work chapter,
  // Tegelaers, KU Leuven, §8.2), which for small moves is
  // a thin shell instead of two whole spheres.
  // `old_ends`/`new_ends`: subtreeEnds() of the two versions (the caller
  // computes them in parallel for a batch).
  void replace(const LightOctree& old_version, const LightOctree& new_version,
               const std::vector<std::uint32_t>& old_ends, const std::vector<std::uint32_t>& new_ends);
  // The same without a geometry mask, the versions given as LightCells:
  // each node's coverage is computed instead of read from an octree, so
  // that no octree is built (a default LightCells stands for no version: an
  // added or removed light). The tree after normalize() is the same.
  void replace(const LightCells& old_version, const LightCells& new_version, std::uint32_t light);
  // Per node of `light`: one past its preorder subtree (what replace() walks by).
  static void subtreeEnds(const LightOctree& light, std::vector<std::uint32_t>& end);
  void normalize();

  void setRecording(bool on) { recording_ = on; }
  // Sorted, unique keys touched since the last call.
  std::vector<std::uint64_t> takeTouched();

  struct NodeView {
    bool exists = false;  // false: inside a leaf above `depth`, or outside
    bool leaf = false;
    const std::vector<std::uint32_t>* lights = nullptr;  // leaves
    std::uint64_t set_sum = 0;  // leaves: LightSetPool::elementHash summed over `lights`
    std::uint8_t leaf_mask = 0, filled_mask = 0;          // branches: the 8 children
  };
  NodeView find(unsigned depth, const glm::uvec3& coord) const;

  // Preorder walk: f(depth, coord, view) for every node.
  template <class F>
  void forEachNode(F&& f) const {
    walk(0, 0, glm::uvec3(0), f);
  }

  struct LayerCounts {
    std::size_t branches = 0, filled_leaves = 0, empty_leaves = 0;
  };
  std::vector<LayerCounts> countsPerDepth() const;
  std::size_t nodeCount() const { return nodes_.size() - 8 * free_blocks_.size(); }
  std::size_t indexEntries() const;  // sum of leaf set sizes
  const OctreeBounds& bounds() const { return b_; }

 private:
  struct Node {
    std::int32_t child = -1;  // first of 8 consecutive children, -1: leaf
    bool dirty = false;
  };
  bool care(unsigned t, const glm::uvec3& c) const { return !mask_ || mask_->has(t, c); }
  bool isLeaf(std::int32_t n) const { return nodes_[n].child < 0; }
  NodeView view(std::int32_t n) const;

  // Touched-key recording (SceneOctreeTouched.cpp), after leaf n's set changed.
  void record(std::int32_t n, unsigned t, const glm::uvec3& c);
  // After node (t, c) was split or merged: it, its parent and its children.
  void recordChildren(unsigned t, const glm::uvec3& c);
  void recordParent(std::uint64_t key);

  // Node storage (SceneOctreeNodes.cpp): children come in blocks of 8;
  // merged blocks are reused before the arrays grow.
  std::int32_t allocBlock();
  void split(std::int32_t n, unsigned t, const glm::uvec3& c);
  bool addToSet(std::int32_t n, std::uint32_t l);
  bool eraseFromSet(std::int32_t n, std::uint32_t l);

  // Tree edits (SceneOctree.cpp).
  // Walks from the scene root towards light octree `lo`'s root r, marking
  // the path dirty; with `split_leaves` leaves on the way are split (insert),
  // else the walk stops at one (remove). Returns the node reached and its
  // (t, c), t < lo.root_depth when it stopped at a leaf; -1 when no
  // geometry lies below (nothing is stored there).
  std::int32_t descend(const LightOctree& lo, unsigned r, bool split_leaves, unsigned& t, glm::uvec3& c);
  void insertRec(std::int32_t n, unsigned t, const glm::uvec3& c, const LightNode*& cur, std::uint32_t l);
  void addFull(std::int32_t n, unsigned t, const glm::uvec3& c, std::uint32_t l);
  void removeRec(std::int32_t n, unsigned t, const glm::uvec3& c, const LightNode*& cur, std::uint32_t l);
  void removeAll(std::int32_t n, unsigned t, const glm::uvec3& c, std::uint32_t l);
  // Leaf n loses light l, if it held it.
  void eraseAndRecord(std::int32_t n, unsigned t, const glm::uvec3& c, std::uint32_t l);
  void normalizeRec(std::int32_t n, unsigned t, const glm::uvec3& c);
  // Coverage of a node by a light during replace(): Above = an ancestor of
  // the light octree's root (partial, no stream read yet).
  enum class Cover : std::uint8_t { Empty = 0, Full = 1, Branch = 2, Above = 3 };
  struct Stream {
    const LightOctree& o;
    const LightNode* cur;
    const std::uint32_t* end;  // per node: one past its preorder subtree
    // After reading a branch (cur is at its first child): past its children.
    const LightNode* branchEnd() const { return o.nodes.data() + end[(cur - o.nodes.data()) - 1]; }
  };
  static constexpr std::uint8_t kNoRoot = 0, kAboveRoot = 1, kHoldsRoot = 2;
  static void aboveChildren(const Stream& s, unsigned t, const glm::uvec3& c, std::uint8_t out[8]);
  static inline Cover childCover(Cover parent, Stream& s, std::uint8_t above);
  static void consume(Cover k, Stream& s) {
    if (k == Cover::Branch) s.cur = s.branchEnd();
  }
  void replaceRec(std::int32_t n, unsigned t, const glm::uvec3& c, Cover ka, Stream& sa, Cover kb, Stream& sb,
                  std::uint32_t l);
  void replaceCellsRec(std::int32_t n, unsigned t, const glm::uvec3& c, LightNode ka, const LightCells& a,
                       LightNode kb, const LightCells& b, std::uint32_t l);

  template <class F>
  void walk(std::int32_t n, unsigned t, const glm::uvec3& c, F& f) const {
    f(t, c, view(n));
    if (!isLeaf(n))
      for (unsigned k = 0; k < 8; ++k) walk(nodes_[n].child + std::int32_t(k), t + 1, childCoord(c, k), f);
  }

  OctreeBounds b_;
  const GeometryMask* mask_;
  std::vector<Node> nodes_;                      // nodes_[0] is the root
  std::vector<std::vector<std::uint32_t>> sets_; // per node; only leaves use theirs
  // Per node, LightSetPool::elementHash summed over sets_[n], kept with every
  // edit, so that normalize() compares sibling sets in O(1) before reading them.
  std::vector<std::uint64_t> sums_;
  std::vector<std::int32_t> free_blocks_;
  bool recording_ = false;
  std::vector<std::uint64_t> touched_;
  std::uint64_t last_parent_ = ~std::uint64_t(0);  // siblings change together: their parent is pushed once
  std::vector<std::uint64_t> sort_scratch_;
};

// The edits' innermost steps, defined here so that the edit walks in
// SceneOctree.cpp inline them (-2.5% instructions in an update's tree step).

inline void SceneOctree::record(std::int32_t n, unsigned t, const glm::uvec3& c) {
  if (!recording_) return;
  touched_.push_back(nodeKey(t, c));
  // The parent's description (its children's leaf/filled bits) changes only
  // when the leaf's set became or stopped being empty; a set of one or none
  // covers both. Most edits leave a set non-empty, and most touched keys
  // would otherwise be such parents, looked up for nothing.
  if (t > 0 && sets_[n].size() <= 1) recordParent(nodeKey(t - 1, c >> 1u));
}

// A parent just recorded is not pushed again (takeTouched() would drop the
// duplicate anyway, after sorting it).
inline void SceneOctree::recordParent(std::uint64_t key) {
  if (key == last_parent_) return;
  touched_.push_back(key);
  last_parent_ = key;
}

inline bool SceneOctree::addToSet(std::int32_t n, std::uint32_t l) {
  auto& s = sets_[n];
  if (s.empty() || s.back() < l) {
    s.push_back(l);  // a light after every one the set holds (the fast path of a sorted insert)
  } else {
    const auto it = std::lower_bound(s.begin(), s.end(), l);
    if (it != s.end() && *it == l) return false;
    s.insert(it, l);
  }
  sums_[n] += LightSetPool::elementHash(l);
  return true;
}

inline bool SceneOctree::eraseFromSet(std::int32_t n, std::uint32_t l) {
  auto& s = sets_[n];
  const auto it = std::lower_bound(s.begin(), s.end(), l);
  if (it == s.end() || *it != l) return false;
  s.erase(it);
  sums_[n] -= LightSetPool::elementHash(l);
  return true;
}

}  // namespace ml::hashed
