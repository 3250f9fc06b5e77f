// compute::RadixSorter against std::stable_sort: uint32 / uint64 keys, with and
// without payload, partial key_bits, both kernel shapes, the sizes and
// key distributions. Payloads are the input indices, so any instability shows.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <numeric>
#include <string>
#include <tuple>
#include <vector>

#include "host/compute/Distributions.hpp"
#include "host/compute/HostIo.hpp"
#include "host/compute/RadixSort.hpp"
#include "support/TestDevice.hpp"
#include "support/TestSizes.hpp"

namespace ml::compute {
namespace {

const std::size_t kBig = (1u << 20) + 7;
const std::size_t kSmallSizes[] = {0, 1, 2, 31, 32, 33, 1023, 1024, 1025};
const KeyDist kDists[] = {KeyDist::Random,   KeyDist::AllEqual,   KeyDist::Sorted,
                          KeyDist::Reversed, KeyDist::AllBitsSet, KeyDist::FewDistinct};

// What is sorted: key width, payload or not, and how many key bits count.
enum class Variant { Keys32, Pairs32, Pairs32Bits13, Pairs64, Keys64Bits40 };

const char* variantName(Variant v) {
  switch (v) {
    case Variant::Keys32:
      return "Keys32";
    case Variant::Pairs32:
      return "Pairs32";
    case Variant::Pairs32Bits13:
      return "Pairs32Bits13";
    case Variant::Pairs64:
      return "Pairs64";
    case Variant::Keys64Bits40:
      return "Keys64Bits40";
  }
  return "?";
}

template <class T>
::testing::AssertionResult sameVectors(const std::vector<T>& got, const std::vector<T>& want, const char* what) {
  if (got.size() != want.size()) return ::testing::AssertionFailure() << what << ": size differs";
  for (std::size_t i = 0; i < got.size(); ++i)
    if (got[i] != want[i])
      return ::testing::AssertionFailure() << what << ": first mismatch at " << i << " of " << got.size()
                                           << ": got " << got[i] << ", want " << want[i];
  return ::testing::AssertionSuccess();
}

template <class K>
void runCase(RadixSorter& sorter, std::size_t n, KeyDist dist, bool with_values, unsigned key_bits,
             std::uint64_t seed) {
  auto& rt = test::runtime();
  auto& q = rt.queue();

  // Keys use all bits even when fewer are sorted: the extra bits must travel
  // with their key without taking part in the order.
  const std::vector<K> keys = makeKeys<K>(n, dist, seed);
  std::vector<std::uint32_t> values(n);
  std::iota(values.begin(), values.end(), 0u);

  // One element of slack past n, poisoned, catches writes beyond the end.
  cl::Buffer key_buf = upload(rt.context(), q, keys, 1);
  cl::Buffer val_buf = upload(rt.context(), q, values, 1);
  const std::uint32_t poison_word = 0xDEADBEEFu;
  q.enqueueFillBuffer(key_buf, poison_word, n * sizeof(K), sizeof(K));
  q.enqueueFillBuffer(val_buf, poison_word, n * 4, 4);

  if constexpr (sizeof(K) == 4)
    sorter.sort(q, key_buf, with_values ? &val_buf : nullptr, n, key_bits);
  else
    sorter.sort64(q, key_buf, with_values ? &val_buf : nullptr, n, key_bits);

  const K mask = key_bits >= sizeof(K) * 8 ? ~K(0) : ((K(1) << key_bits) - 1);
  std::vector<std::uint32_t> order(n);
  std::iota(order.begin(), order.end(), 0u);
  std::stable_sort(order.begin(), order.end(),
                   [&](std::uint32_t a, std::uint32_t b) { return (keys[a] & mask) < (keys[b] & mask); });
  std::vector<K> want_keys(n);
  for (std::size_t i = 0; i < n; ++i) want_keys[i] = keys[order[i]];

  auto got = download<K>(q, key_buf, n + 1);
  EXPECT_EQ(std::uint32_t(got[n]), poison_word) << "wrote past n";
  got.resize(n);
  EXPECT_TRUE(sameVectors(got, want_keys, "keys"));
  auto got_values = download<std::uint32_t>(q, val_buf, n + 1);
  EXPECT_EQ(got_values[n], poison_word) << "wrote past n";
  got_values.resize(n);
  if (with_values)
    EXPECT_TRUE(sameVectors(got_values, order, "payload (stability)"));
  else
    EXPECT_TRUE(sameVectors(got_values, values, "untouched payload"));
}

void runVariant(RadixSorter& sorter, std::size_t n, KeyDist dist, Variant v, std::uint64_t seed) {
  switch (v) {
    case Variant::Keys32:
      return runCase<std::uint32_t>(sorter, n, dist, false, 32, seed);
    case Variant::Pairs32:
      return runCase<std::uint32_t>(sorter, n, dist, true, 32, seed);
    case Variant::Pairs32Bits13:
      return runCase<std::uint32_t>(sorter, n, dist, true, 13, seed);
    case Variant::Pairs64:
      return runCase<std::uint64_t>(sorter, n, dist, true, 64, seed);
    case Variant::Keys64Bits40:
      return runCase<std::uint64_t>(sorter, n, dist, false, 40, seed);
  }
}

// One test per (shape, variant); the sizes and key distributions run
// inside it (CTest starts a process per test), each case with its own seed
// derived from the test's. 2^20 + 7, the expensive size, runs every variant
// on random keys and every distribution on 32-bit pairs.
using RadixParam = std::tuple<Shape, Variant>;

class RadixSortTest : public ::testing::TestWithParam<RadixParam> {};

TEST_P(RadixSortTest, MatchesStableSort) {
  const auto [shape, variant] = GetParam();
  const std::uint64_t seed = test::freshSeed();
  SCOPED_TRACE("seed=" + std::to_string(seed));
  RadixSorter sorter(test::runtime(), Options{.shape = shape});
  for (const KeyDist dist : kDists) {
    std::vector<std::size_t> sizes(std::begin(kSmallSizes), std::end(kSmallSizes));
    if ((dist == KeyDist::Random || variant == Variant::Pairs32) && !test::smallSizes()) sizes.push_back(kBig);
    for (const std::size_t n : sizes) {
      SCOPED_TRACE(std::string(keyDistName(dist)) + " n=" + std::to_string(n));
      runVariant(sorter, n, dist, variant, seed + n * 7 + static_cast<std::uint64_t>(dist));
      if (HasFailure()) return;  // one broken case is enough to read
    }
  }
}

std::string radixName(const ::testing::TestParamInfo<RadixParam>& info) {
  const auto [shape, variant] = info.param;
  return std::string(shape == Shape::CpuChunked ? "Cpu" : "Gpu") + "_" + variantName(variant);
}

INSTANTIATE_TEST_SUITE_P(Compute, RadixSortTest,
                         ::testing::Combine(::testing::Values(Shape::CpuChunked, Shape::GpuWorkGroup),
                                            ::testing::Values(Variant::Keys32, Variant::Pairs32,
                                                              Variant::Pairs32Bits13, Variant::Pairs64,
                                                              Variant::Keys64Bits40)),
                         radixName);

// Tests per shape (the shape in the name, so that a filter can pick one).
class RadixShapeTest : public ::testing::TestWithParam<Shape> {};

TEST_P(RadixShapeTest, DigitWidthsAndOddPassCounts) {
  // Non-default digit widths; 3 and 5 bits give odd pass counts (result
  // copied back from scratch) and a narrower last pass.
  auto& rt = test::runtime();
  auto& q = rt.queue();
  for (unsigned bits : {3u, 5u, 8u}) {
    SCOPED_TRACE("radix_bits=" + std::to_string(bits));
    const std::uint64_t seed = test::freshSeed();
    SCOPED_TRACE("seed=" + std::to_string(seed));
    RadixSorter sorter(rt, Options{.shape = GetParam(), .radix_bits = bits});
    const std::size_t n = test::sizeOr(20000, 3000);
    auto keys = makeKeys<std::uint32_t>(n, KeyDist::Random, seed, 0x3FFFFFu);
    cl::Buffer buf = upload(rt.context(), q, keys);
    sorter.sort(q, buf, nullptr, n, 22);
    std::sort(keys.begin(), keys.end());
    EXPECT_TRUE(sameVectors(download<std::uint32_t>(q, buf, n), keys, "keys"));
  }
}

// Pairs of random keys below `key_mask`, sorted by `key_bits`, against a
// stable sort; the output's slack is poisoned as in runCase.
void runCaseMasked(RadixSorter& sorter, std::size_t n, std::uint32_t key_mask, unsigned key_bits,
                   std::uint64_t seed) {
  auto& rt = test::runtime();
  auto& q = rt.queue();
  const auto keys = makeKeys<std::uint32_t>(n, KeyDist::Random, seed, key_mask);
  std::vector<std::uint32_t> values(n);
  std::iota(values.begin(), values.end(), 0u);
  cl::Buffer kb = upload(rt.context(), q, keys, 1), vb = upload(rt.context(), q, values, 1);
  const std::uint32_t poison = 0xDEADBEEFu;
  q.enqueueFillBuffer(kb, poison, n * 4, 4);
  q.enqueueFillBuffer(vb, poison, n * 4, 4);
  sorter.sort(q, kb, &vb, n, key_bits);
  std::vector<std::uint32_t> order(values);
  std::stable_sort(order.begin(), order.end(), [&](auto a, auto b) { return keys[a] < keys[b]; });
  auto got = download<std::uint32_t>(q, vb, n + 1);
  EXPECT_EQ(got[n], poison) << "wrote past n";
  got.resize(n);
  EXPECT_TRUE(sameVectors(got, order, "payload (narrow keys)"));
  EXPECT_EQ(download<std::uint32_t>(q, kb, n + 1)[n], poison) << "wrote past n";
}

TEST(ComputeRadixSort, CpuWideDigitsAndBalancedPasses) {
  // CPU shape: digits wider than 8 bits run from 2^16 keys on (default 11):
  // every key_bits splits into balanced passes (32 -> 11 + 11 + 10, 20 ->
  // 10 + 10, 13 -> 7 + 6), each pass counting only its own digits. 2^16 + 3
  // keys: the smallest size that takes them, odd so that chunks end mid-line.
  const std::size_t n = (std::size_t(1) << 16) + 3;
  for (unsigned bits : {9u, 11u, 12u}) {
    SCOPED_TRACE("radix_bits=" + std::to_string(bits));
    const std::uint64_t seed = test::freshSeed();
    SCOPED_TRACE("seed=" + std::to_string(seed));
    RadixSorter sorter(test::runtime(), Options{.shape = Shape::CpuChunked, .radix_bits = bits});
    for (unsigned key_bits : {32u, 20u, 13u, 1u}) {
      SCOPED_TRACE("key_bits=" + std::to_string(key_bits));
      runCase<std::uint32_t>(sorter, n, KeyDist::Random, true, key_bits, seed + key_bits);
      runCase<std::uint32_t>(sorter, n, KeyDist::FewDistinct, false, key_bits, seed ^ key_bits);
      if (HasFailure()) return;
    }
    // Keys narrower than key_bits: the top pass finds every chunk on one
    // digit and moves it as a block (the copy path of radix_scatter).
    runCaseMasked(sorter, n, 0xFFFFFu, 32, seed + 99);
    runCase<std::uint64_t>(sorter, n, KeyDist::Random, true, 64, seed + 64);
    runCase<std::uint64_t>(sorter, n, KeyDist::AllBitsSet, false, 45, seed + 45);
  }
}

TEST(ComputeRadixSort, FreeFunctionsAndReuseAcrossSizes) {
  const std::uint64_t seed = test::freshSeed();
  SCOPED_TRACE("seed=" + std::to_string(seed));
  auto& rt = test::runtime();
  auto& q = rt.queue();
  // Growing then shrinking n reuses (and grows) the shared sorter's scratch.
  for (std::size_t n : test::smallSizes() ? std::vector<std::size_t>{100, 3000, 5, 4100}
                                          : std::vector<std::size_t>{100, 70000, 5, 300000}) {
    auto keys = makeKeys<std::uint32_t>(n, KeyDist::Random, seed + n);
    std::vector<std::uint32_t> values(n);
    std::iota(values.begin(), values.end(), 0u);
    cl::Buffer kb = upload(rt.context(), q, keys), vb = upload(rt.context(), q, values);
    radix_sort(q, kb, &vb, n, 32);
    std::vector<std::uint32_t> order(values);
    std::stable_sort(order.begin(), order.end(), [&](auto a, auto b) { return keys[a] < keys[b]; });
    EXPECT_TRUE(sameVectors(download<std::uint32_t>(q, vb, n), order, "payload"));
    auto keys64 = makeKeys<std::uint64_t>(n, KeyDist::Random, seed ^ n);
    cl::Buffer kb64 = upload(rt.context(), q, keys64);
    radix_sort64(q, kb64, nullptr, n);
    std::sort(keys64.begin(), keys64.end());
    EXPECT_TRUE(sameVectors(download<std::uint64_t>(q, kb64, n), keys64, "keys64"));
  }
}

TEST_P(RadixShapeTest, UnalignedHostPointerBuffers) {
  // The CPU scatter streams whole 64-byte lines when the buffers allow it; a
  // buffer over an unaligned host allocation must still sort correctly.
  const std::uint64_t seed = test::freshSeed();
  SCOPED_TRACE("seed=" + std::to_string(seed));
  auto& rt = test::runtime();
  auto& q = rt.queue();
  const std::size_t n = test::sizeOr(100003, 3001);
  auto keys = makeKeys<std::uint32_t>(n, KeyDist::Random, seed);
  std::vector<std::uint32_t> key_store(n + 1), val_store(n + 3);
  std::copy(keys.begin(), keys.end(), key_store.begin() + 1);
  for (std::size_t i = 0; i < n; ++i) val_store[i + 3] = static_cast<std::uint32_t>(i);
  cl::Buffer kb(rt.context(), CL_MEM_READ_WRITE | CL_MEM_USE_HOST_PTR, n * 4, key_store.data() + 1);
  cl::Buffer vb(rt.context(), CL_MEM_READ_WRITE | CL_MEM_USE_HOST_PTR, n * 4, val_store.data() + 3);
  RadixSorter sorter(rt, Options{.shape = GetParam()});
  sorter.sort(q, kb, &vb, n, 32);
  std::vector<std::uint32_t> order(n);
  std::iota(order.begin(), order.end(), 0u);
  std::stable_sort(order.begin(), order.end(), [&](auto a, auto b) { return keys[a] < keys[b]; });
  EXPECT_TRUE(sameVectors(download<std::uint32_t>(q, vb, n), order, "payload"));
}

INSTANTIATE_TEST_SUITE_P(Compute, RadixShapeTest, ::testing::Values(Shape::CpuChunked, Shape::GpuWorkGroup),
                         [](const ::testing::TestParamInfo<Shape>& info) {
                           return std::string(info.param == Shape::CpuChunked ? "Cpu" : "Gpu");
                         });

TEST(ComputeRadixSort, RejectsBadArguments) {
  auto& rt = test::runtime();
  RadixSorter sorter(rt);
  cl::Buffer buf(rt.context(), CL_MEM_READ_WRITE, 64);
  EXPECT_THROW(sorter.sort(rt.queue(), buf, nullptr, 16, 33), std::invalid_argument);
  EXPECT_THROW(sorter.sort(rt.queue(), buf, nullptr, 17, 32), std::invalid_argument);
  EXPECT_THROW(sorter.sort(rt.queue(), buf, &buf, 4, 32), std::invalid_argument);
  EXPECT_THROW(sorter.sort64(rt.queue(), buf, nullptr, 9, 64), std::invalid_argument);
}

}  // namespace
}  // namespace ml::compute
