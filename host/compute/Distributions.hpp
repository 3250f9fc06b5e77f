#pragma once
// Key distributions the primitives are tested and benchmarked on (the cases
// that break sorts: duplicates, presorted runs, extreme values).
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <random>
#include <string>
#include <vector>

namespace ml::compute {

enum class KeyDist { Random, AllEqual, Sorted, Reversed, AllBitsSet, FewDistinct };

inline const char* keyDistName(KeyDist d) {
  switch (d) {
    case KeyDist::Random:
      return "Random";
    case KeyDist::AllEqual:
      return "AllEqual";
    case KeyDist::Sorted:
      return "Sorted";
    case KeyDist::Reversed:
      return "Reversed";
    case KeyDist::AllBitsSet:
      return "AllBitsSet";
    case KeyDist::FewDistinct:
      return "FewDistinct";
  }
  return "?";
}

// n keys of type T (uint32_t or uint64_t) drawn from `dist`; `mask` limits the
// random bits (e.g. to key_bits). Sorted/Reversed contain duplicates too, so
// that stability is visible in them.
template <class T>
std::vector<T> makeKeys(std::size_t n, KeyDist dist, std::uint64_t seed, T mask = ~T(0)) {
  std::mt19937_64 rng(seed);
  std::vector<T> k(n);
  switch (dist) {
    case KeyDist::Random:
      for (auto& x : k) x = static_cast<T>(rng()) & mask;
      break;
    case KeyDist::AllEqual: {
      const T v = static_cast<T>(rng()) & mask;
      std::fill(k.begin(), k.end(), v);
      break;
    }
    case KeyDist::Sorted:
    case KeyDist::Reversed:
      for (auto& x : k) x = static_cast<T>(rng()) & mask;
      // Every value about twice: equal neighbours exercise stability.
      for (std::size_t i = 1; i < n; i += 2) k[i] = k[i - 1];
      std::sort(k.begin(), k.end());
      if (dist == KeyDist::Reversed) std::reverse(k.begin(), k.end());
      break;
    case KeyDist::AllBitsSet:
      std::fill(k.begin(), k.end(), mask);
      // A few smaller keys so the all-ones keys still have to move.
      for (std::size_t i = 0; i < n; i += 97) k[i] = static_cast<T>(rng()) & mask;
      break;
    case KeyDist::FewDistinct: {
      T values[5];
      for (auto& v : values) v = static_cast<T>(rng()) & mask;
      for (auto& x : k) x = values[rng() % 5];
      break;
    }
  }
  return k;
}

}  // namespace ml::compute
