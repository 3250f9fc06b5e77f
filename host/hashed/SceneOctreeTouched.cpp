// The scene octree's touched-key recording: which nodes' hash entries an
// edit may have changed. Contract: SceneOctree.hpp.
#include "host/hashed/KeySort.hpp"
#include "host/hashed/SceneOctree.hpp"

namespace ml::hashed {

void SceneOctree::recordChildren(unsigned t, const glm::uvec3& c) {
  if (!recording_) return;
  touched_.push_back(nodeKey(t, c));
  if (t > 0) recordParent(nodeKey(t - 1, c >> 1u));
  for (unsigned k = 0; k < 8; ++k) touched_.push_back(nodeKey(t + 1, childCoord(c, k)));
}

std::vector<std::uint64_t> SceneOctree::takeTouched() {
  std::vector<std::uint64_t> out;
  out.swap(touched_);
  last_parent_ = ~std::uint64_t(0);
  sortUniqueKeys(out, sort_scratch_);
  return out;
}

}  // namespace ml::hashed
