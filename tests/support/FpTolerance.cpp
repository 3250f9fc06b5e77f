#include "support/FpTolerance.hpp"

#include <algorithm>
#include <cmath>
#include <iterator>
#include <limits>

#include "support/TestDevice.hpp"

namespace ml::test {

bool exactDivideSqrt() { return correctlyRoundedDivideSqrt(runtime().info().single_fp_config); }

namespace {
std::size_t symmetricDifference(std::vector<std::uint32_t> a, std::vector<std::uint32_t> b) {
  std::sort(a.begin(), a.end());
  std::sort(b.begin(), b.end());
  std::vector<std::uint32_t> d;
  std::set_symmetric_difference(a.begin(), a.end(), b.begin(), b.end(), std::back_inserter(d));
  return d.size();
}
}  // namespace

::testing::AssertionResult listsMatch(const Lists& got, const Lists& ref, const std::string& what, bool exact) {
  if (got.size() != ref.size())
    return ::testing::AssertionFailure() << what << ": " << got.size() << " lists, expected " << ref.size();
  const std::size_t allowed = exact ? 0 : std::max<std::size_t>(1, ref.size() / 100);
  std::size_t differing = 0;
  for (std::size_t k = 0; k < ref.size(); ++k) {
    if (got[k] == ref[k]) continue;
    if (exact) return ::testing::AssertionFailure() << what << " " << k << ": lists differ (exact division)";
    const std::size_t d = symmetricDifference(got[k], ref[k]);
    if (d > 2) return ::testing::AssertionFailure() << what << " " << k << ": " << d << " entries differ (tolerance 2)";
    if (++differing > allowed)
      return ::testing::AssertionFailure() << what << ": more than " << allowed << " lists differ (tolerance 1%)";
  }
  return ::testing::AssertionSuccess();
}

::testing::AssertionResult valuesMatch(const std::vector<std::uint32_t>& got, const std::vector<std::uint32_t>& ref,
                                       const std::string& what, bool exact) {
  if (got.size() != ref.size())
    return ::testing::AssertionFailure() << what << ": " << got.size() << " values, expected " << ref.size();
  const std::size_t allowed = exact ? 0 : std::max<std::size_t>(1, ref.size() / 1000);
  std::size_t differing = 0;
  for (std::size_t p = 0; p < ref.size(); ++p) {
    if (got[p] == ref[p]) continue;
    if (++differing > allowed)
      return ::testing::AssertionFailure() << what << " " << p << ": " << got[p] << ", expected " << ref[p] << " ("
                                           << differing << " differ, tolerance " << allowed << ")";
  }
  return ::testing::AssertionSuccess();
}

bool floatsMatch(float got, float ref, bool exact) {
  if (exact || got == ref) return got == ref;
  return std::fabs(got - ref) <= 8.0f * 0x1p-23f * std::max(std::fabs(ref), std::numeric_limits<float>::min());
}

}  // namespace ml::test
