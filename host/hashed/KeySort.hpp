#pragma once
// Sorting the node keys an update touched (a few thousand to a few hundred
// thousand, many repeated): LSD radix sort by 11-bit digits, skipping digits
// that are equal in every key (node keys use 52 bits, and the high depth and
// coordinate bits rarely vary), then dropping repeats. Contract: `keys` ends
// up sorted ascending without duplicates, exactly as std::sort + std::unique
// would leave it; `scratch` is reused storage (contents unspecified).
#include <cstdint>
#include <vector>

namespace ml::hashed {

void sortUniqueKeys(std::vector<std::uint64_t>& keys, std::vector<std::uint64_t>& scratch);

}  // namespace ml::hashed
