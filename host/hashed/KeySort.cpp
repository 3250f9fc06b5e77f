#include "host/hashed/KeySort.hpp"

#include <algorithm>

namespace ml::hashed {

void sortUniqueKeys(std::vector<std::uint64_t>& keys, std::vector<std::uint64_t>& scratch) {
  if (keys.size() < kRadixSortMinItems) std::sort(keys.begin(), keys.end());
  else radixSortBy(keys, scratch, [](std::uint64_t k) { return k; });
  keys.erase(std::unique(keys.begin(), keys.end()), keys.end());
}

}  // namespace ml::hashed
