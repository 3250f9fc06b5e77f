// compute::Compactor: stable compaction (values and indices) against
// std::copy_if, unique on sorted keys against std::unique, both kernel shapes.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <random>
#include <string>
#include <tuple>
#include <vector>

#include "host/compute/Compact.hpp"
#include "host/compute/Distributions.hpp"
#include "host/compute/HostIo.hpp"
#include "support/TestDevice.hpp"
#include "support/TestSizes.hpp"

namespace ml::compute {
namespace {

// MANYLIGHTS_TEST_SMALL drops the last size (see support/TestSizes.hpp).
std::vector<std::size_t> testSizes() {
  return test::sizesUpToLimit({0, 1, 2, 31, 32, 33, 1023, 1024, 1025, (1u << 20) + 7});
}
constexpr std::uint32_t kPoison = 0xDEADBEEFu;

enum class Density { None, All, Half, Sparse };

const char* densityName(Density d) {
  switch (d) {
    case Density::None:
      return "None";
    case Density::All:
      return "All";
    case Density::Half:
      return "Half";
    case Density::Sparse:
      return "Sparse";
  }
  return "?";
}

std::vector<std::uint32_t> makeFlags(std::size_t n, Density d, std::mt19937_64& rng) {
  std::vector<std::uint32_t> f(n);
  for (auto& x : f) {
    switch (d) {
      case Density::None:
        x = 0;
        break;
      case Density::All:
        x = 1 + static_cast<std::uint32_t>(rng() % 7);  // any non-zero value keeps
        break;
      case Density::Half:
        x = static_cast<std::uint32_t>(rng() & 1) * static_cast<std::uint32_t>(rng());
        break;
      case Density::Sparse:
        x = rng() % 100 == 0;
        break;
    }
  }
  return f;
}

template <class T>
::testing::AssertionResult samePrefix(const std::vector<T>& got, const std::vector<T>& want) {
  for (std::size_t i = 0; i < want.size(); ++i)
    if (got[i] != want[i])
      return ::testing::AssertionFailure() << "first mismatch at " << i << " of " << want.size() << ": got " << got[i]
                                           << ", want " << want[i];
  return ::testing::AssertionSuccess();
}

// One test per (shape, flag density) and per (shape, key distribution); the
// issue's sizes run inside each (CTest starts a process per test), each with
// its own seed derived from the test's.
using CompactParam = std::tuple<Shape, Density>;
class CompactTest : public ::testing::TestWithParam<CompactParam> {};

TEST_P(CompactTest, ValuesAndIndicesMatchCopyIf) {
  const auto [shape, density] = GetParam();
  const std::uint64_t seed = test::freshSeed();
  SCOPED_TRACE("seed=" + std::to_string(seed));
  auto& rt = test::runtime();
  auto& q = rt.queue();
  Compactor compactor(rt, Options{.shape = shape});
  for (const std::size_t n : testSizes()) {
    SCOPED_TRACE("n=" + std::to_string(n));
    std::mt19937_64 rng(seed + n);
    std::vector<std::uint32_t> in(n);
    for (auto& x : in) x = static_cast<std::uint32_t>(rng());
    const auto flags = makeFlags(n, density, rng);
    cl::Buffer in_buf = upload(rt.context(), q, in), flag_buf = upload(rt.context(), q, flags);
    cl::Buffer out(rt.context(), CL_MEM_READ_WRITE, (n + 1) * 4);

    std::vector<std::uint32_t> want, want_idx;
    for (std::size_t i = 0; i < n; ++i)
      if (flags[i]) {
        want.push_back(in[i]);
        want_idx.push_back(static_cast<std::uint32_t>(i));
      }

    poison(q, out);
    const std::size_t count = compactor.compact(q, in_buf, flag_buf, out, n);
    ASSERT_EQ(count, want.size());
    auto got = download<std::uint32_t>(q, out, n + 1);
    EXPECT_TRUE(samePrefix(got, want));
    EXPECT_EQ(got[n], kPoison) << "wrote past n";

    poison(q, out);
    ASSERT_EQ(compactor.compactIndices(q, flag_buf, out, n), want_idx.size());
    got = download<std::uint32_t>(q, out, n + 1);
    EXPECT_TRUE(samePrefix(got, want_idx));
    EXPECT_EQ(got[n], kPoison) << "wrote past n";

    // The non-blocking form leaves the count on the device.
    poison(q, out);
    cl::Buffer count_buf(rt.context(), CL_MEM_READ_WRITE, 8);
    poison(q, count_buf);
    compactor.compactAsync(q, in_buf, flag_buf, out, n, count_buf, 1);
    const auto counts = download<std::uint32_t>(q, count_buf, 2);
    EXPECT_EQ(counts[0], kPoison);
    EXPECT_EQ(counts[1], want.size());
    EXPECT_TRUE(samePrefix(download<std::uint32_t>(q, out, n), want));
  }
}

std::string compactName(const ::testing::TestParamInfo<CompactParam>& info) {
  const auto [shape, density] = info.param;
  return std::string(shape == Shape::CpuChunked ? "Cpu" : "Gpu") + "_" + densityName(density);
}

INSTANTIATE_TEST_SUITE_P(Compute, CompactTest,
                         ::testing::Combine(::testing::Values(Shape::CpuChunked, Shape::GpuWorkGroup),
                                            ::testing::Values(Density::None, Density::All, Density::Half,
                                                              Density::Sparse)),
                         compactName);

using UniqueParam = std::tuple<Shape, KeyDist>;
class UniqueTest : public ::testing::TestWithParam<UniqueParam> {};

TEST_P(UniqueTest, MatchesStdUnique) {
  const auto [shape, dist] = GetParam();
  const std::uint64_t seed = test::freshSeed();
  SCOPED_TRACE("seed=" + std::to_string(seed));
  auto& rt = test::runtime();
  auto& q = rt.queue();
  Compactor compactor(rt, Options{.shape = shape});
  for (const std::size_t n : testSizes()) {
    SCOPED_TRACE("n=" + std::to_string(n));
    // Small value ranges make long runs of duplicates.
    auto keys = makeKeys<std::uint32_t>(n, dist, seed + n, dist == KeyDist::Random ? 0x3FFu : 0xFFFFFFFFu);
    std::sort(keys.begin(), keys.end());
    cl::Buffer key_buf = upload(rt.context(), q, keys);
    cl::Buffer out(rt.context(), CL_MEM_READ_WRITE, (n + 1) * 4);
    poison(q, out);
    const std::size_t count = compactor.unique(q, key_buf, out, n);
    std::vector<std::uint32_t> want(keys);
    want.erase(std::unique(want.begin(), want.end()), want.end());
    ASSERT_EQ(count, want.size());
    auto got = download<std::uint32_t>(q, out, n + 1);
    EXPECT_TRUE(samePrefix(got, want));
    EXPECT_EQ(got[n], kPoison) << "wrote past n";
  }
}

std::string uniqueName(const ::testing::TestParamInfo<UniqueParam>& info) {
  const auto [shape, dist] = info.param;
  return std::string(shape == Shape::CpuChunked ? "Cpu" : "Gpu") + "_" + keyDistName(dist);
}

INSTANTIATE_TEST_SUITE_P(Compute, UniqueTest,
                         ::testing::Combine(::testing::Values(Shape::CpuChunked, Shape::GpuWorkGroup),
                                            ::testing::Values(KeyDist::Random, KeyDist::AllEqual, KeyDist::Sorted,
                                                              KeyDist::AllBitsSet, KeyDist::FewDistinct)),
                         uniqueName);

TEST(ComputeCompact, FreeFunctionsAndAliasing) {
  const std::uint64_t seed = test::freshSeed();
  SCOPED_TRACE("seed=" + std::to_string(seed));
  auto& rt = test::runtime();
  auto& q = rt.queue();
  std::vector<std::uint32_t> in = {5, 5, 6, 9, 9, 9, 12};
  std::vector<std::uint32_t> flags = {1, 0, 1, 0, 0, 1, 1};
  cl::Buffer in_buf = upload(rt.context(), q, in), flag_buf = upload(rt.context(), q, flags);
  cl::Buffer out(rt.context(), CL_MEM_READ_WRITE, in.size() * 4);
  EXPECT_EQ(compact(q, in_buf, flag_buf, out, in.size()), 4u);
  EXPECT_EQ(download<std::uint32_t>(q, out, 4), (std::vector<std::uint32_t>{5, 6, 9, 12}));
  EXPECT_EQ(unique(q, in_buf, out, in.size()), 4u);
  EXPECT_EQ(download<std::uint32_t>(q, out, 4), (std::vector<std::uint32_t>{5, 6, 9, 12}));
  Compactor c(rt);
  EXPECT_THROW(c.compact(q, in_buf, flag_buf, in_buf, in.size()), std::invalid_argument);
  EXPECT_THROW(c.unique(q, in_buf, in_buf, in.size()), std::invalid_argument);
  EXPECT_THROW(c.compact(q, in_buf, flag_buf, out, in.size() + 1), std::invalid_argument);
}

}  // namespace
}  // namespace ml::compute
