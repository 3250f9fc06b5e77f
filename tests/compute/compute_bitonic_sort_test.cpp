// compute::BitonicSorter against std::sort: keys and key-value pairs, any n,
// both kernel shapes, default and tiny fast-memory blocks (the latter push
// even small inputs through the cross-block global stages).
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <numeric>
#include <string>
#include <tuple>
#include <vector>

#include "host/compute/BitonicSort.hpp"
#include "host/compute/Distributions.hpp"
#include "host/compute/HostIo.hpp"
#include "support/TestDevice.hpp"
#include "support/TestSizes.hpp"

namespace ml::compute {
namespace {

const std::size_t kBig = (1u << 20) + 7;
const std::size_t kSmallSizes[] = {0, 1, 2, 31, 32, 33, 1023, 1024, 1025};
const KeyDist kDists[] = {KeyDist::Random,   KeyDist::AllEqual,   KeyDist::Sorted,
                          KeyDist::Reversed, KeyDist::AllBitsSet, KeyDist::FewDistinct};
constexpr std::uint32_t kPoison = 0xDEADBEEFu;

// Default blocks, or the smallest ones (16 elements per CPU work-item, 8
// work-items per GPU work-group).
enum class Blocks { Default, Tiny };

Options optionsFor(Shape shape, Blocks blocks) {
  Options o{.shape = shape};
  if (blocks == Blocks::Tiny) {
    if (shape == Shape::CpuChunked)
      o.sort_chunk = 16;
    else
      o.work_group_size = 8;
  }
  return o;
}

void runCase(BitonicSorter& sorter, std::size_t n, KeyDist dist, bool with_values, std::uint64_t seed) {
  auto& rt = test::runtime();
  auto& q = rt.queue();
  const auto keys = makeKeys<std::uint32_t>(n, dist, seed);
  std::vector<std::uint32_t> values(n);
  std::iota(values.begin(), values.end(), 0u);
  cl::Buffer kb = upload(rt.context(), q, keys, 1), vb = upload(rt.context(), q, values, 1);
  q.enqueueFillBuffer(kb, kPoison, n * 4, 4);
  q.enqueueFillBuffer(vb, kPoison, n * 4, 4);
  sorter.sort(q, kb, with_values ? &vb : nullptr, n);

  auto want = keys;
  std::sort(want.begin(), want.end());
  auto got = download<std::uint32_t>(q, kb, n + 1);
  ASSERT_EQ(got[n], kPoison) << "wrote past n";
  got.resize(n);
  for (std::size_t i = 0; i < n; ++i) ASSERT_EQ(got[i], want[i]) << "key mismatch at " << i << " of " << n;

  auto got_values = download<std::uint32_t>(q, vb, n + 1);
  ASSERT_EQ(got_values[n], kPoison) << "wrote past n";
  got_values.resize(n);
  if (with_values) {
    // Not stable, but each payload must still sit next to its own key, and
    // each exactly once.
    std::vector<char> seen(n, 0);
    for (std::size_t i = 0; i < n; ++i) {
      const std::uint32_t v = got_values[i];
      ASSERT_LT(v, n) << "payload garbage at " << i;
      ASSERT_FALSE(seen[v]) << "payload " << v << " duplicated";
      seen[v] = 1;
      ASSERT_EQ(keys[v], got[i]) << "payload " << v << " separated from its key at " << i;
    }
  } else {
    ASSERT_EQ(got_values, values) << "key-only sort touched the payload";
  }
}

// One test per (shape, block size, keys or pairs); the sizes and key
// distributions run inside it (CTest starts a process per test), each case
// with its own seed derived from the test's. 2^20 + 7 costs ~20 global passes
// per sort: it runs on random keys, and with payloads on every distribution
// on the CPU shape (ties and padding with payloads attached).
using BitonicParam = std::tuple<Shape, Blocks, bool>;
class BitonicSortTest : public ::testing::TestWithParam<BitonicParam> {};

TEST_P(BitonicSortTest, MatchesStdSort) {
  const auto [shape, blocks, with_values] = GetParam();
  const std::uint64_t seed = test::freshSeed();
  SCOPED_TRACE("seed=" + std::to_string(seed));
  BitonicSorter sorter(test::runtime(), optionsFor(shape, blocks));
  for (const KeyDist dist : kDists) {
    std::vector<std::size_t> sizes(std::begin(kSmallSizes), std::end(kSmallSizes));
    if (blocks == Blocks::Default && (dist == KeyDist::Random || (shape == Shape::CpuChunked && with_values)) &&
        !test::smallSizes())
      sizes.push_back(kBig);
    for (const std::size_t n : sizes) {
      SCOPED_TRACE(std::string(keyDistName(dist)) + " n=" + std::to_string(n));
      runCase(sorter, n, dist, with_values, seed + n * 7 + static_cast<std::uint64_t>(dist));
      if (HasFailure()) return;  // one broken case is enough to read
    }
  }
}

std::string bitonicName(const ::testing::TestParamInfo<BitonicParam>& info) {
  const auto [shape, blocks, with_values] = info.param;
  return std::string(shape == Shape::CpuChunked ? "Cpu" : "Gpu") + (blocks == Blocks::Tiny ? "TinyBlocks" : "") +
         (with_values ? "_Pairs" : "_Keys");
}

INSTANTIATE_TEST_SUITE_P(Compute, BitonicSortTest,
                         ::testing::Combine(::testing::Values(Shape::CpuChunked, Shape::GpuWorkGroup),
                                            ::testing::Values(Blocks::Default, Blocks::Tiny), ::testing::Bool()),
                         bitonicName);

TEST(ComputeBitonicSort, FreeFunctionAndBadArguments) {
  const std::uint64_t seed = test::freshSeed();
  SCOPED_TRACE("seed=" + std::to_string(seed));
  auto& rt = test::runtime();
  auto& q = rt.queue();
  auto keys = makeKeys<std::uint32_t>(test::sizeOr(70001, 3001), KeyDist::Random, seed);
  cl::Buffer kb = upload(rt.context(), q, keys);
  bitonic_sort(q, kb, nullptr, keys.size());
  std::sort(keys.begin(), keys.end());
  EXPECT_EQ(download<std::uint32_t>(q, kb, keys.size()), keys);
  BitonicSorter s(rt);
  EXPECT_THROW(s.sort(q, kb, &kb, 10), std::invalid_argument);
  EXPECT_THROW(s.sort(q, kb, nullptr, keys.size() + 1), std::invalid_argument);
}

}  // namespace
}  // namespace ml::compute
