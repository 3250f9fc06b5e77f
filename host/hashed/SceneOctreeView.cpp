// The scene octree's read-only queries: node views, lookups by key and by
// cell, counts. Contract: SceneOctree.hpp.
#include "host/hashed/SceneOctree.hpp"

namespace ml::hashed {

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
