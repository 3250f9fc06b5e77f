#pragma once
// The small-size switch of the kernel tests: MANYLIGHTS_TEST_SMALL=1 keeps only
// their small inputs, for runs under a simulator ~1000x slower than PoCL
// (scripts/oclgrind.sh). Small sizes still cover 0, 1, odd counts and powers of
// two +-1 around the tile and work-group boundaries; only the sizes that exist
// to exercise extra levels or throughput are dropped.
#include <cstddef>
#include <initializer_list>
#include <vector>

namespace ml::test {

// True when MANYLIGHTS_TEST_SMALL is set to anything but "" or "0".
bool smallSizes();

// The largest input a kernel test uses under the switch.
inline constexpr std::size_t kSmallLimit = 4100;

// `sizes` in order, without those above kSmallLimit when smallSizes().
std::vector<std::size_t> sizesUpToLimit(std::initializer_list<std::size_t> sizes);

// `normal`, or `small` under the switch (for single-size tests).
inline std::size_t sizeOr(std::size_t normal, std::size_t small) { return smallSizes() ? small : normal; }

}  // namespace ml::test
