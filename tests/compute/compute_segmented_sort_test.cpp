// compute::SegmentedSorter: every segment against std::sort of that segment,
// fixed-size and offset segments (empty, tiny, and longer than the GPU shape's
// local memory), keys and pairs, both kernel shapes; elements outside all
// segments must stay untouched.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <numeric>
#include <random>
#include <string>
#include <tuple>
#include <vector>

#include "host/compute/Distributions.hpp"
#include "host/compute/HostIo.hpp"
#include "host/compute/SegmentedSort.hpp"
#include "support/TestDevice.hpp"
#include "support/TestSizes.hpp"

namespace ml::compute {
namespace {

const std::size_t kBig = (1u << 20) + 7;
// MANYLIGHTS_TEST_SMALL drops kBig (see support/TestSizes.hpp).
std::vector<std::size_t> testSizes() { return test::sizesUpToLimit({0, 1, 2, 31, 32, 33, 1023, 1024, 1025, kBig}); }
const KeyDist kDists[] = {KeyDist::Random,   KeyDist::AllEqual,   KeyDist::Sorted,
                          KeyDist::Reversed, KeyDist::AllBitsSet, KeyDist::FewDistinct};
constexpr std::uint32_t kPoison = 0xDEADBEEFu;

// Sorts on the device and checks against the host; `offsets` has one entry
// more than there are segments.
void sortAndCheck(SegmentedSorter& sorter, const std::vector<std::uint32_t>& keys,
                  const std::vector<std::uint32_t>& offsets, bool with_values, std::size_t fixed_size,
                  std::size_t max_segment = 0) {
  auto& rt = test::runtime();
  auto& q = rt.queue();
  const std::size_t n = keys.size();
  const std::size_t segs = offsets.size() - 1;
  std::vector<std::uint32_t> values(n);
  std::iota(values.begin(), values.end(), 0u);
  cl::Buffer kb = upload(rt.context(), q, keys, 1), vb = upload(rt.context(), q, values, 1);
  q.enqueueFillBuffer(kb, kPoison, n * 4, 4);
  q.enqueueFillBuffer(vb, kPoison, n * 4, 4);
  cl::Buffer ob = upload(rt.context(), q, offsets);
  if (fixed_size)
    sorter.sortFixed(q, kb, with_values ? &vb : nullptr, n, fixed_size);
  else
    sorter.sort(q, kb, with_values ? &vb : nullptr, n, ob, segs, nullptr, max_segment);

  auto got = download<std::uint32_t>(q, kb, n + 1);
  auto got_values = download<std::uint32_t>(q, vb, n + 1);
  ASSERT_EQ(got[n], kPoison) << "wrote past n";
  ASSERT_EQ(got_values[n], kPoison) << "wrote past n";
  std::vector<char> covered(n, 0);
  for (std::size_t s = 0; s < segs; ++s) {
    const std::size_t b = offsets[s], e = offsets[s + 1];
    std::vector<std::uint32_t> want(keys.begin() + b, keys.begin() + e);
    std::sort(want.begin(), want.end());
    std::vector<char> seen(e - b, 0);
    for (std::size_t i = b; i < e; ++i) {
      covered[i] = 1;
      ASSERT_EQ(got[i], want[i - b]) << "segment " << s << " [" << b << ", " << e << ") at " << i;
      if (with_values) {
        const std::uint32_t v = got_values[i];
        ASSERT_TRUE(v >= b && v < e) << "payload left its segment at " << i;
        ASSERT_FALSE(seen[v - b]) << "payload " << v << " duplicated";
        seen[v - b] = 1;
        ASSERT_EQ(keys[v], got[i]) << "payload separated from its key at " << i;
      }
    }
  }
  for (std::size_t i = 0; i < n; ++i)
    if (!covered[i]) {
      ASSERT_EQ(got[i], keys[i]) << "element outside every segment moved at " << i;
      ASSERT_EQ(got_values[i], values[i]) << "payload outside every segment moved at " << i;
    }
  if (!with_values) {
    for (std::size_t i = 0; i < n; ++i) ASSERT_EQ(got_values[i], values[i]) << "key-only sort touched payload";
  }
}

// One test per (shape, keys or pairs); the sizes and key
// distributions run inside it (CTest starts a process per test), each with its
// own seed derived from the test's. Tile-sized (256) segments, the last one
// partial; 2^20 + 7 on random keys, and on every distribution on the CPU shape.
using FixedParam = std::tuple<Shape, bool>;
class SegmentedSortFixedTest : public ::testing::TestWithParam<FixedParam> {};

TEST_P(SegmentedSortFixedTest, EverySegmentSorted) {
  const auto [shape, with_values] = GetParam();
  const std::uint64_t seed = test::freshSeed();
  SCOPED_TRACE("seed=" + std::to_string(seed));
  SegmentedSorter sorter(test::runtime(), Options{.shape = shape});
  const std::size_t size = 256;
  for (const KeyDist dist : kDists)
    for (const std::size_t n : testSizes()) {
      if (n == kBig && dist != KeyDist::Random && shape != Shape::CpuChunked) continue;
      SCOPED_TRACE(std::string(keyDistName(dist)) + " n=" + std::to_string(n));
      std::vector<std::uint32_t> offsets;
      for (std::size_t b = 0; b < n; b += size) offsets.push_back(static_cast<std::uint32_t>(b));
      offsets.push_back(static_cast<std::uint32_t>(n));
      sortAndCheck(sorter, makeKeys<std::uint32_t>(n, dist, seed + n * 7 + static_cast<std::uint64_t>(dist)), offsets,
                   with_values, size);
      if (HasFailure()) return;  // one broken case is enough to read
    }
}

std::string fixedName(const ::testing::TestParamInfo<FixedParam>& info) {
  const auto [shape, with_values] = info.param;
  return std::string(shape == Shape::CpuChunked ? "Cpu" : "Gpu") + (with_values ? "_Pairs" : "_Keys");
}

const auto kShapes = ::testing::Values(Shape::CpuChunked, Shape::GpuWorkGroup);

INSTANTIATE_TEST_SUITE_P(Compute, SegmentedSortFixedTest, ::testing::Combine(kShapes, ::testing::Bool()), fixedName);

class SegmentedSortShapeTest : public ::testing::TestWithParam<Shape> {};

TEST_P(SegmentedSortShapeTest, FixedSizesAroundPowersOfTwo) {
  const std::uint64_t seed = test::freshSeed();
  SCOPED_TRACE("seed=" + std::to_string(seed));
  SegmentedSorter sorter(test::runtime(), Options{.shape = GetParam()});
  for (std::size_t size : {1u, 2u, 3u, 31u, 32u, 33u, 1000u, 5000u}) {
    SCOPED_TRACE("segment_size=" + std::to_string(size));
    const std::size_t n = test::sizeOr(20011, 2011);
    std::vector<std::uint32_t> offsets;
    for (std::size_t b = 0; b < n; b += size) offsets.push_back(static_cast<std::uint32_t>(b));
    offsets.push_back(static_cast<std::uint32_t>(n));
    sortAndCheck(sorter, makeKeys<std::uint32_t>(n, KeyDist::Random, seed + size), offsets, true, size);
  }
}

TEST_P(SegmentedSortShapeTest, OffsetSegmentsWithGapsEmptyAndLong) {
  const std::uint64_t seed = test::freshSeed();
  SCOPED_TRACE("seed=" + std::to_string(seed));
  SegmentedSorter sorter(test::runtime(), Options{.shape = GetParam()});
  std::mt19937_64 rng(seed);
  // Variable lengths (0 .. 600), one segment longer than the GPU shape's
  // local capacity, and a tail past the last segment that must not move.
  const int nseg = test::smallSizes() ? 10 : 500;
  std::vector<std::uint32_t> offsets{0};
  for (int s = 0; s < nseg; ++s) {
    const std::uint32_t len = s == nseg / 2 ? static_cast<std::uint32_t>(sorter.localCapacity() * 3 + 5)
                                       : static_cast<std::uint32_t>(rng() % 601) * (rng() % 5 != 0);
    offsets.push_back(offsets.back() + len);
  }
  const std::size_t n = offsets.back() + 777;
  for (KeyDist dist : {KeyDist::Random, KeyDist::AllBitsSet, KeyDist::FewDistinct})
    for (bool with_values : {false, true}) {
      SCOPED_TRACE(std::string(keyDistName(dist)) + (with_values ? " pairs" : " keys"));
      sortAndCheck(sorter, makeKeys<std::uint32_t>(n, dist, rng()), offsets, with_values, 0);
    }
}

// The caller's bound on segment lengths (a tile's pixels): the GPU shape runs
// only next_pow2(bound)'s stages, exact for segments up to the bound, lengths
// around powers of two included; a segment past the bound stays unsorted there,
// which shows the bound really cuts the stages.
TEST_P(SegmentedSortShapeTest, OffsetSegmentsWithAStatedBound) {
  const std::uint64_t seed = test::freshSeed();
  SCOPED_TRACE("seed=" + std::to_string(seed));
  SegmentedSorter sorter(test::runtime(), Options{.shape = GetParam()});
  std::mt19937_64 rng(seed);
  for (std::size_t bound : {1u, 31u, 256u, 1024u}) {
    SCOPED_TRACE("bound=" + std::to_string(bound));
    std::vector<std::uint32_t> offsets{0};
    for (int s = 0; s < 300; ++s) {
      const std::size_t len = s % 7 == 0 ? bound : rng() % (bound + 1);
      offsets.push_back(offsets.back() + static_cast<std::uint32_t>(len));
    }
    const std::size_t n = offsets.back() + 5;
    sortAndCheck(sorter, makeKeys<std::uint32_t>(n, KeyDist::Random, rng()), offsets, true, 0, bound);
    if (GetParam() == Shape::GpuWorkGroup) {
      EXPECT_EQ(sorter.lastStageBound(), detail::nextPow2(bound));
    }
  }
  if (GetParam() != Shape::GpuWorkGroup) return;
  auto& rt = test::runtime();
  auto& q = rt.queue();
  std::vector<std::uint32_t> keys(64);
  for (std::size_t i = 0; i < keys.size(); ++i) keys[i] = static_cast<std::uint32_t>(keys.size() - i);
  const std::vector<std::uint32_t> offsets{0, 64};
  cl::Buffer kb = upload(rt.context(), q, keys), ob = upload(rt.context(), q, offsets);
  sorter.sort(q, kb, nullptr, keys.size(), ob, 1, nullptr, 8);
  const auto got = download<std::uint32_t>(q, kb, keys.size());
  EXPECT_FALSE(std::is_sorted(got.begin(), got.end())) << "a bound of 8 ran the stages of 64";
  EXPECT_TRUE(std::is_sorted(got.begin(), got.begin() + 8)) << "runs of the bound are sorted";
}

INSTANTIATE_TEST_SUITE_P(Compute, SegmentedSortShapeTest, kShapes,
                         [](const ::testing::TestParamInfo<Shape>& info) {
                           return std::string(info.param == Shape::CpuChunked ? "Cpu" : "Gpu");
                         });

TEST(ComputeSegmentedSort, FreeFunctionClampsOffsetsAndRejectsBadArguments) {
  auto& rt = test::runtime();
  auto& q = rt.queue();
  std::vector<std::uint32_t> keys = {9, 3, 7, 1, 8, 2};
  // The second segment's end (100) is past n: clamped to n.
  std::vector<std::uint32_t> offsets = {0, 3, 100};
  cl::Buffer kb = upload(rt.context(), q, keys), ob = upload(rt.context(), q, offsets);
  segmented_sort(q, kb, nullptr, keys.size(), ob, 2);
  EXPECT_EQ(download<std::uint32_t>(q, kb, keys.size()), (std::vector<std::uint32_t>{3, 7, 9, 1, 2, 8}));
  SegmentedSorter s(rt);
  EXPECT_THROW(s.sortFixed(q, kb, nullptr, keys.size(), 0), std::invalid_argument);
  EXPECT_THROW(s.sort(q, kb, nullptr, keys.size(), ob, 5), std::invalid_argument);
  EXPECT_THROW(s.sort(q, kb, &kb, keys.size(), ob, 2), std::invalid_argument);
}

}  // namespace
}  // namespace ml::compute
