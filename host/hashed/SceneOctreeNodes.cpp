// The scene octree's node storage: blocks of 8 children (reusing the
// blocks that merges freed), splits, and the leaves' sorted light sets with
// their element-hash sums. Contract: SceneOctree.hpp.
#include <algorithm>

#include "host/hashed/SceneOctree.hpp"

namespace ml::hashed {

std::int32_t SceneOctree::allocBlock() {
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
void SceneOctree::split(std::int32_t n, unsigned t, const glm::uvec3& c) {
  const std::int32_t block = allocBlock();
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
  recordChildren(t, c);
}

}  // namespace ml::hashed
