// The scene octree's touched-key recording: which nodes' hash entries an
// edit may have changed. Contract: SceneOctree.hpp.
#include "host/hashed/KeySort.hpp"
#include "host/hashed/SceneOctree.hpp"

namespace ml::hashed {

void SceneOctree::record(std::int32_t n, unsigned t, const glm::uvec3& c) {
  if (!recording_) return;
  touched_.push_back(nodeKey(t, c));
  // The parent's description (its children's leaf/filled bits) changes only
  // when the leaf's set became or stopped being empty; a set of one or none
  // covers both. Most edits leave a set non-empty, and most touched keys
  // would otherwise be such parents, looked up for nothing.
  if (t > 0 && sets_[n].size() <= 1) recordParent(nodeKey(t - 1, c >> 1u));
}

void SceneOctree::recordChildren(unsigned t, const glm::uvec3& c) {
  if (!recording_) return;
  touched_.push_back(nodeKey(t, c));
  if (t > 0) recordParent(nodeKey(t - 1, c >> 1u));
  for (unsigned k = 0; k < 8; ++k) touched_.push_back(nodeKey(t + 1, childCoord(c, k)));
}

// A parent just recorded is not pushed again (takeTouched() would drop the
// duplicate anyway, after sorting it).
void SceneOctree::recordParent(std::uint64_t key) {
  if (key == last_parent_) return;
  touched_.push_back(key);
  last_parent_ = key;
}

std::vector<std::uint64_t> SceneOctree::takeTouched() {
  std::vector<std::uint64_t> out;
  out.swap(touched_);
  last_parent_ = ~std::uint64_t(0);
  sortUniqueKeys(out, sort_scratch_);
  return out;
}

}  // namespace ml::hashed
