#pragma once
// Comparing kernel results with their C++ twins when float division and sqrt
// may not be correctly rounded. Programs build with
// -cl-fp32-correctly-rounded-divide-sqrt where the device offers it
// (host/cl/ClRuntime.hpp: correctlyRoundedDivideSqrt); then results must match
// bit for bit. Elsewhere CL 1.2 allows 2.5-ulp division and 3-ulp sqrt, so a
// light or pixel within a few ulps of a plane may land on the other side, and
// the stated tolerance applies instead:
//   - lists (per tile / cluster): at most 1% of the lists (and at least 1) may
//     differ, each by at most 2 entries (symmetric difference);
//   - per-pixel values (cluster keys): at most 0.1% of the pixels (and at
//     least 1) may differ;
//   - floats: within 8 ulps, i.e. 8 * 2^-23 relative, of the twin's value.
// Conservativeness checks (every light that reaches a point is listed) stay
// exact in both cases: they test the technique, not the rounding.
#include <gtest/gtest.h>

#include <cstdint>
#include <string>
#include <vector>

namespace ml::test {

// Whether the shared test runtime's programs divide and sqrt correctly rounded
// (queried from the device, honouring the MANYLIGHTS_TEST_INEXACT_DIVIDE hook).
bool exactDivideSqrt();

using Lists = std::vector<std::vector<std::uint32_t>>;
// Exact: every list equal. Otherwise within the list tolerance above.
::testing::AssertionResult listsMatch(const Lists& got, const Lists& ref, const std::string& what,
                                      bool exact = exactDivideSqrt());
::testing::AssertionResult valuesMatch(const std::vector<std::uint32_t>& got, const std::vector<std::uint32_t>& ref,
                                       const std::string& what, bool exact = exactDivideSqrt());
bool floatsMatch(float got, float ref, bool exact = exactDivideSqrt());

}  // namespace ml::test
