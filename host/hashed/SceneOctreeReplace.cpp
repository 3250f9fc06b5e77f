// SceneOctree's joint walks of a light's old and new versions (replace():
// Tables 8.1/8.2 per node where the versions' coverage differs), by light
// octrees or by computed coverage (LightCells). Contract: SceneOctree.hpp.
#include <algorithm>
#include <bit>

#include "host/hashed/SceneOctree.hpp"

namespace ml::hashed {

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

void SceneOctree::replace(const LightOctree& a, const LightOctree& b, const std::vector<std::uint32_t>* ends_a,
                          const std::vector<std::uint32_t>* ends_b) {
  if (!ends_a) {
    subtreeEnds(a, end_a_);
    ends_a = &end_a_;
  }
  if (!ends_b) {
    subtreeEnds(b, end_b_);
    ends_b = &end_b_;
  }
  Stream sa{a, a.nodes.data(), ends_a->data()}, sb{b, b.nodes.data(), ends_b->data()};
  auto top = [](const LightOctree& o, Stream& s) {
    if (o.empty()) return Cover::Empty;
    return o.root_depth == 0 ? Cover(*s.cur++) : Cover::Above;  // depth 0: the one root is the scene root
  };
  const Cover ka = top(a, sa), kb = top(b, sb);
  replaceRec(main_, 0, 0, glm::uvec3(0), ka, sa, kb, sb, b.light);
}

void SceneOctree::replaceRec(Lane& ln, std::int32_t n, unsigned t, const glm::uvec3& c, Cover ka, Stream& sa, Cover kb,
                             Stream& sb, std::uint32_t l) {
  const bool pa = ka == Cover::Branch || ka == Cover::Above, pb = kb == Cover::Branch || kb == Cover::Above;
  if (!care(t, c) || (!pa && !pb && ka == kb)) {  // nothing stored here, or no change
    consume(ka, sa);
    consume(kb, sb);
    return;
  }
  if (!pa && !pb) {  // whole node gained or lost the light
    if (kb == Cover::Full) addFull(ln, n, t, c, l);
    else removeAll(ln, n, t, c, l);
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
      if (kb == Cover::Full) addFull(ln, n, t, c, l);
      else if (eraseFromSet(n, l)) record(ln, n, t, c);
      return;
    }
    split(ln, n, t, c);  // Table 8.1: the new version covers part of the leaf
  }
  const std::int32_t ch = nodes_[n].child;
  std::uint8_t above_a[8] = {}, above_b[8] = {};
  if (ka == Cover::Above) aboveChildren(sa, t, c, above_a);
  if (kb == Cover::Above) aboveChildren(sb, t, c, above_b);
  for (unsigned k = 0; k < 8; ++k) {
    const glm::uvec3 cc = childCoord(c, k);
    const Cover ca = childCover(ka, sa, above_a[k]), cb = childCover(kb, sb, above_b[k]);
    if (ca == cb && (ca == Cover::Empty || ca == Cover::Full)) continue;  // unchanged here
    replaceRec(ln, ch + std::int32_t(k), t + 1, cc, ca, sa, cb, sb, l);
  }
}

void SceneOctree::replace(const LightCells& a, const LightCells& b, std::uint32_t l) {
  const glm::uvec3 root(0);
  replaceCellsRec(main_, 0, 0, root, a.cover(0, root), a, b.cover(0, root), b, l);
}

// replaceRec() with computed coverage (Branch: partly covered).
void SceneOctree::replaceCellsRec(Lane& ln, std::int32_t n, unsigned t, const glm::uvec3& c, LightNode ka, const LightCells& a,
                                  LightNode kb, const LightCells& b, std::uint32_t l) {
  const bool pa = ka == LightNode::Branch, pb = kb == LightNode::Branch;
  if (!care(t, c) || (!pa && !pb && ka == kb)) return;  // nothing stored here, or no change
  if (!pa && !pb) {  // whole node gained or lost the light
    if (kb == LightNode::Full) addFull(ln, n, t, c, l);
    else removeAll(ln, n, t, c, l);
    return;
  }
  nodes_[n].dirty = true;
  if (isLeaf(n)) {
    if (!pb) {  // the new version covers this leaf entirely or not at all
      if (kb == LightNode::Full) addFull(ln, n, t, c, l);
      else if (eraseFromSet(n, l)) record(ln, n, t, c);
      return;
    }
    split(ln, n, t, c);  // Table 8.1: the new version covers part of the leaf
  }
  const std::int32_t ch = nodes_[n].child;
  if (t + 1 == b_.depth) {  // the children are cells: Full or Empty
    const unsigned ma = pa ? a.cellMask(c) : (ka == LightNode::Full ? 0xFFu : 0u);
    const unsigned mb = pb ? b.cellMask(c) : (kb == LightNode::Full ? 0xFFu : 0u);
    for (unsigned diff = ma ^ mb; diff != 0; diff &= diff - 1) {
      const unsigned k = unsigned(std::countr_zero(diff));
      const glm::uvec3 cc = childCoord(c, k);
      if (!care(t + 1, cc)) continue;
      if ((mb >> k) & 1u) addFull(ln, ch + std::int32_t(k), t + 1, cc, l);
      else removeAll(ln, ch + std::int32_t(k), t + 1, cc, l);
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
    replaceCellsRec(ln, ch + std::int32_t(k), t + 1, childCoord(c, k), kind(fa, ba, k), a, kind(fb, bb, k), b, l);
  }
}

}  // namespace ml::hashed
