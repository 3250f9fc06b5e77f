// The scene octree's edits: Table 7.1 inserts, Table 8.2 removals, the
// joint old/new walks of replace() (Tables 8.1/8.2, by light octrees or by
// LightCells) and the canonical merge. Node storage is in
// SceneOctreeNodes.cpp, touched-key recording in SceneOctreeTouched.cpp,
// the read-only queries in SceneOctreeView.cpp. Contract: SceneOctree.hpp.
#include "host/hashed/SceneOctree.hpp"

#include <algorithm>
#include <bit>

namespace ml::hashed {
namespace {

void skipChildren(const LightNode*& cur) {
  for (int k = 0; k < 8; ++k) skipLightSubtree(cur);
}

}  // namespace

SceneOctree::SceneOctree(const OctreeBounds& bounds, const GeometryMask* mask) : b_(bounds), mask_(mask) {
  nodes_.emplace_back();
  sets_.emplace_back();
  sums_.push_back(0);
}

std::int32_t SceneOctree::descend(const LightOctree& lo, unsigned r, bool split_leaves, unsigned& t,
                                  glm::uvec3& c) {
  std::int32_t n = 0;
  t = 0;
  c = glm::uvec3(0);
  while (t < lo.root_depth) {
    if (!care(t, c)) return -1;
    if (isLeaf(n)) {
      if (!split_leaves) return n;
      split(n, t, c);
    }
    nodes_[n].dirty = true;
    c = lo.roots[r] >> (lo.root_depth - t - 1);
    n = nodes_[n].child + std::int32_t(childBit(c));
    ++t;
  }
  return n;
}

void SceneOctree::insert(const LightOctree& lo) {
  for (unsigned r = 0; r < lo.root_count; ++r) {
    unsigned t;
    glm::uvec3 c;
    const std::int32_t n = descend(lo, r, true, t, c);
    if (n < 0) continue;
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
    addFull(n, t, c, l);
    return;
  }
  nodes_[n].dirty = true;
  if (isLeaf(n)) split(n, t, c);
  const std::int32_t ch = nodes_[n].child;
  for (unsigned k = 0; k < 8; ++k) insertRec(ch + std::int32_t(k), t + 1, childCoord(c, k), cur, l);
}

// Table 7.1, full light node: added to a leaf, or to every child of a branch.
void SceneOctree::addFull(std::int32_t n, unsigned t, const glm::uvec3& c, std::uint32_t l) {
  if (!care(t, c)) return;
  nodes_[n].dirty = true;
  if (isLeaf(n)) {
    if (t > b_.start_depth) {
      if (addToSet(n, l)) record(n, t, c);
      return;
    }
    split(n, t, c);  // no non-empty leaves at or above the start depth
  }
  const std::int32_t ch = nodes_[n].child;
  for (unsigned k = 0; k < 8; ++k) addFull(ch + std::int32_t(k), t + 1, childCoord(c, k), l);
}

void SceneOctree::remove(const LightOctree& lo) {
  for (unsigned r = 0; r < lo.root_count; ++r) {
    unsigned t;
    glm::uvec3 c;
    const std::int32_t n = descend(lo, r, false, t, c);
    if (n < 0) continue;
    if (t < lo.root_depth) {  // a leaf above the light's root holds it for all of its cells or none
      eraseAndRecord(n, t, c, lo.light);
      continue;
    }
    const LightNode* cur = lo.nodes.data() + lo.root_start[r];
    removeRec(n, t, c, cur, lo.light);
  }
}

void SceneOctree::eraseAndRecord(std::int32_t n, unsigned t, const glm::uvec3& c, std::uint32_t l) {
  if (!eraseFromSet(n, l)) return;
  nodes_[n].dirty = true;
  record(n, t, c);
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
    eraseAndRecord(n, t, c, l);
    if (type == LightNode::Branch) skipChildren(cur);
    return;
  }
  nodes_[n].dirty = true;
  if (type == LightNode::Full) {
    removeAll(n, t, c, l);
    return;
  }
  const std::int32_t ch = nodes_[n].child;
  for (unsigned k = 0; k < 8; ++k) removeRec(ch + std::int32_t(k), t + 1, childCoord(c, k), cur, l);
}

void SceneOctree::removeAll(std::int32_t n, unsigned t, const glm::uvec3& c, std::uint32_t l) {
  if (isLeaf(n)) {
    eraseAndRecord(n, t, c, l);
    return;
  }
  nodes_[n].dirty = true;
  const std::int32_t ch = nodes_[n].child;
  for (unsigned k = 0; k < 8; ++k) removeAll(ch + std::int32_t(k), t + 1, childCoord(c, k), l);
}

// end[i] = one past node i's preorder subtree, for every root's subtree.
void SceneOctree::subtreeEnds(const LightOctree& o, std::vector<std::uint32_t>& end) {
  end.resize(o.nodes.size());
  std::uint32_t stack[kMaxDepth + 1], pending[kMaxDepth + 1];  // open branches, children left to close
  for (unsigned r = 0; r < o.root_count; ++r) {
    // Iterative preorder: a branch's end is known once its 8th child ends.
    std::uint32_t i = o.root_start[r];
    int top = 0;
    for (;;) {
      if (o.nodes[i] == LightNode::Branch) {
        stack[top] = i;
        pending[top++] = 8;
        ++i;
        continue;
      }
      end[i] = i + 1;
      std::uint32_t e = i + 1;
      while (top > 0 && --pending[top - 1] == 0) end[stack[--top]] = e;
      if (top == 0) break;
      i = e;
    }
  }
}

// Above a light octree's roots: which children of node (t, c) hold a root
// (kHoldsRoot + r when the child is root r) or lie above one; one pass over
// the roots per node instead of one per child.
void SceneOctree::aboveChildren(const Stream& s, unsigned t, const glm::uvec3& c, std::uint8_t out[8]) {
  std::fill(out, out + 8, kNoRoot);
  const unsigned below = s.o.root_depth - t - 1;  // root_depth > t here
  for (unsigned r = 0; r < s.o.root_count; ++r) {
    const glm::uvec3 cc = s.o.roots[r] >> below;
    if ((cc >> 1u) != c) continue;
    out[childBit(cc)] = below == 0 ? std::uint8_t(kHoldsRoot + r) : kAboveRoot;
  }
}

inline SceneOctree::Cover SceneOctree::childCover(Cover parent, Stream& s, std::uint8_t above) {
  switch (parent) {
    case Cover::Empty: return Cover::Empty;
    case Cover::Full: return Cover::Full;
    case Cover::Branch: return Cover(*s.cur++);
    case Cover::Above:
      if (above == kNoRoot) return Cover::Empty;
      if (above == kAboveRoot) return Cover::Above;
      s.cur = s.o.nodes.data() + s.o.root_start[above - kHoldsRoot];
      return Cover(*s.cur++);
  }
  return Cover::Empty;
}

void SceneOctree::replace(const LightOctree& a, const LightOctree& b, const std::vector<std::uint32_t>& ends_a,
                          const std::vector<std::uint32_t>& ends_b) {
  Stream sa{a, a.nodes.data(), ends_a.data()}, sb{b, b.nodes.data(), ends_b.data()};
  auto top = [](const LightOctree& o, Stream& s) {
    if (o.empty()) return Cover::Empty;
    return o.root_depth == 0 ? Cover(*s.cur++) : Cover::Above;  // depth 0: the one root is the scene root
  };
  const Cover ka = top(a, sa), kb = top(b, sb);
  replaceRec(0, 0, glm::uvec3(0), ka, sa, kb, sb, b.light);
}

void SceneOctree::replaceRec(std::int32_t n, unsigned t, const glm::uvec3& c, Cover ka, Stream& sa, Cover kb,
                             Stream& sb, std::uint32_t l) {
  const bool pa = ka == Cover::Branch || ka == Cover::Above, pb = kb == Cover::Branch || kb == Cover::Above;
  if (!care(t, c) || (!pa && !pb && ka == kb)) {  // nothing stored here, or no change
    consume(ka, sa);
    consume(kb, sb);
    return;
  }
  if (!pa && !pb) {  // whole node gained or lost the light
    if (kb == Cover::Full) addFull(n, t, c, l);
    else removeAll(n, t, c, l);
    return;
  }
  if (ka == Cover::Branch && kb == Cover::Branch) {
    // Identical subtrees (the light's edge did not move here): nothing to do.
    const LightNode *ea = sa.branchEnd(), *eb = sb.branchEnd();
    if (ea - sa.cur == eb - sb.cur && std::equal(sa.cur, ea, sb.cur)) {
      sa.cur = ea;
      sb.cur = eb;
      return;
    }
  }
  nodes_[n].dirty = true;
  if (isLeaf(n)) {
    if (!pb) {  // the new version covers this leaf entirely or not at all
      consume(ka, sa);
      if (kb == Cover::Full) addFull(n, t, c, l);
      else if (eraseFromSet(n, l)) record(n, t, c);
      return;
    }
    split(n, t, c);  // Table 8.1: the new version covers part of the leaf
  }
  const std::int32_t ch = nodes_[n].child;
  std::uint8_t above_a[8] = {}, above_b[8] = {};
  if (ka == Cover::Above) aboveChildren(sa, t, c, above_a);
  if (kb == Cover::Above) aboveChildren(sb, t, c, above_b);
  for (unsigned k = 0; k < 8; ++k) {
    const glm::uvec3 cc = childCoord(c, k);
    const Cover ca = childCover(ka, sa, above_a[k]), cb = childCover(kb, sb, above_b[k]);
    if (ca == cb && (ca == Cover::Empty || ca == Cover::Full)) continue;  // unchanged here
    replaceRec(ch + std::int32_t(k), t + 1, cc, ca, sa, cb, sb, l);
  }
}

void SceneOctree::replace(const LightCells& a, const LightCells& b, std::uint32_t l) {
  const glm::uvec3 root(0);
  replaceCellsRec(0, 0, root, a.cover(0, root), a, b.cover(0, root), b, l);
}

// replaceRec() with computed coverage (Branch: partly covered).
void SceneOctree::replaceCellsRec(std::int32_t n, unsigned t, const glm::uvec3& c, LightNode ka, const LightCells& a,
                                  LightNode kb, const LightCells& b, std::uint32_t l) {
  const bool pa = ka == LightNode::Branch, pb = kb == LightNode::Branch;
  if (!care(t, c) || (!pa && !pb && ka == kb)) return;  // nothing stored here, or no change
  if (!pa && !pb) {  // whole node gained or lost the light
    if (kb == LightNode::Full) addFull(n, t, c, l);
    else removeAll(n, t, c, l);
    return;
  }
  nodes_[n].dirty = true;
  if (isLeaf(n)) {
    if (!pb) {  // the new version covers this leaf entirely or not at all
      if (kb == LightNode::Full) addFull(n, t, c, l);
      else if (eraseFromSet(n, l)) record(n, t, c);
      return;
    }
    split(n, t, c);  // Table 8.1: the new version covers part of the leaf
  }
  const std::int32_t ch = nodes_[n].child;
  if (t + 1 == b_.depth) {  // the children are cells: Full or Empty
    const unsigned ma = pa ? a.cellMask(c) : (ka == LightNode::Full ? 0xFFu : 0u);
    const unsigned mb = pb ? b.cellMask(c) : (kb == LightNode::Full ? 0xFFu : 0u);
    for (unsigned diff = ma ^ mb; diff != 0; diff &= diff - 1) {
      const unsigned k = unsigned(std::countr_zero(diff));
      const glm::uvec3 cc = childCoord(c, k);
      if (!care(t + 1, cc)) continue;
      if ((mb >> k) & 1u) addFull(ch + std::int32_t(k), t + 1, cc, l);
      else removeAll(ch + std::int32_t(k), t + 1, cc, l);
    }
    return;
  }
  std::uint8_t fa = ka == LightNode::Full ? 0xFF : 0, ba = 0, fb = kb == LightNode::Full ? 0xFF : 0, bb = 0;
  if (pa) a.childCovers(t, c, fa, ba);
  if (pb) b.childCovers(t, c, fb, bb);
  auto kind = [](std::uint8_t full, std::uint8_t branch, unsigned k) {
    return (branch >> k) & 1u ? LightNode::Branch : (full >> k) & 1u ? LightNode::Full : LightNode::Empty;
  };
  // Children that differ, or that both versions cut through; the rest are unchanged.
  for (unsigned m = unsigned(fa ^ fb) | unsigned(ba ^ bb) | ba; m != 0; m &= m - 1) {
    const unsigned k = unsigned(std::countr_zero(m));
    replaceCellsRec(ch + std::int32_t(k), t + 1, childCoord(c, k), kind(fa, ba, k), a, kind(fb, bb, k), b, l);
  }
}

void SceneOctree::normalize() {
  normalizeRec(0, 0, glm::uvec3(0));
}

void SceneOctree::normalizeRec(std::int32_t n, unsigned t, const glm::uvec3& c) {
  if (!nodes_[n].dirty) return;
  nodes_[n].dirty = false;
  if (isLeaf(n)) return;
  const std::int32_t ch = nodes_[n].child;
  for (unsigned k = 0; k < 8; ++k) normalizeRec(ch + std::int32_t(k), t + 1, childCoord(c, k));
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
  free_blocks_.push_back(ch);
  recordChildren(t, c);
}

}  // namespace ml::hashed
