#pragma once
// Colours for ids in debug views (clustered's clusters, hashed's octree
// cells): neighbouring ids get unrelated colours, distinct in an 8-bit image
// for up to 2^18 ids, and none of them black (black is the sky).
#include <cstdint>

#include "host/util/Heatmap.hpp"

namespace ml {

// Neighbouring ids have neighbouring values, so the id is mixed first, by a
// bijection of 18 bits (odd multiply, xor-shift); the 18 bits then give 6 per
// channel at levels 64 + 3v.
inline Rgb idColour(std::uint32_t id) {
  std::uint32_t h = id & 0x3ffffu;
  h = (h * 0x2c9e5u) & 0x3ffffu;
  h ^= h >> 9;
  h = (h * 0x1b873u) & 0x3ffffu;
  h ^= h >> 7;
  auto level = [&](int c) { return float(64u + 3u * ((h >> (6 * c)) & 0x3fu)) / 255.0f; };
  return {level(0), level(1), level(2)};
}

}  // namespace ml
