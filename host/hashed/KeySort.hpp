#pragma once
// Sorting the node keys an update touched (a few thousand to a few hundred
// thousand, many repeated): LSD radix sort by 11-bit digits, skipping digits
// that are equal in every key (node keys use 52 bits, and the high depth and
// coordinate bits rarely vary), then dropping repeats. Contract: `keys` ends
// up sorted ascending without duplicates, exactly as std::sort + std::unique
// would leave it; `scratch` is reused storage (contents unspecified).
#include <algorithm>
#include <array>
#include <cstdint>
#include <vector>

namespace ml::hashed {

// Below this many items, comparison sorting beats clearing and scanning
// the radix sort's histograms.
constexpr std::size_t kRadixSortMinItems = 512;

void sortUniqueKeys(std::vector<std::uint64_t>& keys, std::vector<std::uint64_t>& scratch);

// The radix sort itself, by key(item) (64 bits), stable; `items` not empty.
template <class T, class Key>
void radixSortBy(std::vector<T>& items, std::vector<T>& scratch, Key key) {
  constexpr unsigned kBits = 11, kPasses = (64 + kBits - 1) / kBits;
  constexpr std::size_t kBuckets = std::size_t(1) << kBits;
  auto digit = [&](const T& t, unsigned p) { return (std::uint64_t(key(t)) >> (p * kBits)) & (kBuckets - 1); };
  std::vector<std::array<std::uint32_t, kBuckets>> count(kPasses);
  for (auto& c : count) c.fill(0);
  for (const T& t : items)
    for (unsigned p = 0; p < kPasses; ++p) ++count[p][digit(t, p)];
  scratch.resize(items.size());
  for (unsigned p = 0; p < kPasses; ++p) {
    auto& c = count[p];
    // A digit shared by every item leaves the order as it is.
    if (c[digit(items[0], p)] == items.size()) continue;
    std::uint32_t sum = 0;
    for (auto& x : c) {
      const std::uint32_t n = x;
      x = sum;
      sum += n;
    }
    for (const T& t : items) scratch[c[digit(t, p)]++] = t;
    items.swap(scratch);
  }
}

// Records sorted by their `key` member the same way, stably (records with
// equal keys keep their order), repeats kept.
template <class T>
void sortByKeyStable(std::vector<T>& items, std::vector<T>& scratch) {
  if (items.size() < kRadixSortMinItems) {
    std::stable_sort(items.begin(), items.end(), [](const T& a, const T& b) { return a.key < b.key; });
    return;
  }
  radixSortBy(items, scratch, [](const T& t) { return t.key; });
}

}  // namespace ml::hashed
