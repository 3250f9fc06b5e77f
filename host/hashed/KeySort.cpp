#include "host/hashed/KeySort.hpp"

#include <algorithm>
#include <array>

namespace ml::hashed {

void sortUniqueKeys(std::vector<std::uint64_t>& keys, std::vector<std::uint64_t>& scratch) {
  // Below this, comparison sorting beats clearing and scanning histograms.
  if (keys.size() < 512) {
    std::sort(keys.begin(), keys.end());
  } else {
    constexpr unsigned kBits = 11, kPasses = (64 + kBits - 1) / kBits;
    constexpr std::size_t kBuckets = std::size_t(1) << kBits;
    std::vector<std::array<std::uint32_t, kBuckets>> count(kPasses);
    for (auto& c : count) c.fill(0);
    for (const std::uint64_t k : keys)
      for (unsigned p = 0; p < kPasses; ++p) ++count[p][(k >> (p * kBits)) & (kBuckets - 1)];
    scratch.resize(keys.size());
    for (unsigned p = 0; p < kPasses; ++p) {
      auto& c = count[p];
      // A digit shared by every key leaves the order as it is.
      if (c[(keys[0] >> (p * kBits)) & (kBuckets - 1)] == keys.size()) continue;
      std::uint32_t sum = 0;
      for (auto& x : c) {
        const std::uint32_t n = x;
        x = sum;
        sum += n;
      }
      for (const std::uint64_t k : keys) scratch[c[(k >> (p * kBits)) & (kBuckets - 1)]++] = k;
      keys.swap(scratch);
    }
  }
  keys.erase(std::unique(keys.begin(), keys.end()), keys.end());
}

}  // namespace ml::hashed
