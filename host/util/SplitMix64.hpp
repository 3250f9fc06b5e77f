#pragma once
// splitmix64 (Steele et al. 2014): a small, fast, seedable stream, seeded
// in a few instructions (the standard engines cost a full state
// initialisation each), whose output does not depend on the standard
// library's generator implementations (the hash tables must not).
#include <cstdint>

namespace ml {

struct SplitMix64 {
  static constexpr std::uint64_t kGolden = 0x9E3779B97F4A7C15ull;
  std::uint64_t s;
  std::uint64_t next() { return mix(s += kGolden); }
  // The output function on its own: a bijective 64-bit mix (also a hash).
  static std::uint64_t mix(std::uint64_t z) {
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
  }
  // Uniform in [0, n).
  std::uint32_t below(std::uint32_t n) { return std::uint32_t((next() >> 32) * n >> 32); }
  // Uniform in [0, 1), 24 bits.
  float uniform() { return float(next() >> 40) * 0x1.0p-24f; }
};

}  // namespace ml
