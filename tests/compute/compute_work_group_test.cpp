// The GPU shape of every compute primitive at forced work-group sizes (32, 64,
// 256 and the device maximum), against its C++ twin on fresh random inputs:
// the kernels must not depend on one group size, and a size a kernel cannot
// run with is lowered to one it can (rusticl's llvmpipe runs many of them with
// at most 32 items), never refused. Sizes straddle the tiles of every
// work-group size here (WG * 4 elements: 128 .. 4096), with duplicates.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <numeric>
#include <random>
#include <string>
#include <tuple>
#include <vector>

#include "host/compute/BitonicSort.hpp"
#include "host/compute/Compact.hpp"
#include "host/compute/Distributions.hpp"
#include "host/compute/HostIo.hpp"
#include "host/compute/RadixSort.hpp"
#include "host/compute/Reduce.hpp"
#include "host/compute/Scan.hpp"
#include "host/compute/SegmentedSort.hpp"
#include "support/TestDevice.hpp"
#include "support/TestSizes.hpp"

namespace ml::compute {
namespace {

constexpr std::uint32_t kPoison = 0xDEADBEEFu;

enum class Prim { Scan, Reduce, Compact, Radix, Bitonic, Segmented };

const char* primName(Prim p) {
  switch (p) {
    case Prim::Scan: return "Scan";
    case Prim::Reduce: return "Reduce";
    case Prim::Compact: return "Compact";
    case Prim::Radix: return "Radix";
    case Prim::Bitonic: return "Bitonic";
    case Prim::Segmented: return "Segmented";
  }
  return "?";
}

std::vector<std::size_t> sizes() { return test::sizesUpToLimit({0, 1, 2, 31, 33, 127, 129, 1025, 4095, 4097, 70001}); }

// 0 in the parameter stands for the device maximum (a power of two or the
// largest one below it).
std::size_t requestedSize(std::size_t p) {
  if (p) return p;
  std::size_t m = 1;
  while (m * 2 <= test::runtime().info().max_work_group_size) m *= 2;
  return m;
}

Options gpuOptions(std::size_t wg) { return Options{.shape = Shape::GpuWorkGroup, .work_group_size = wg}; }

// The group size a primitive settled on: a power of two, at most the request.
void checkSettled(std::size_t got, std::size_t requested) {
  EXPECT_GE(got, 1u);
  EXPECT_LE(got, requested);
  EXPECT_EQ(got & (got - 1), 0u) << got << " is not a power of two";
}

template <class T>
::testing::AssertionResult same(const std::vector<T>& got, const std::vector<T>& want, const char* what) {
  if (got.size() != want.size()) return ::testing::AssertionFailure() << what << ": size differs";
  for (std::size_t i = 0; i < got.size(); ++i)
    if (got[i] != want[i])
      return ::testing::AssertionFailure() << what << ": first mismatch at " << i << " of " << got.size() << ": got "
                                           << got[i] << ", want " << want[i];
  return ::testing::AssertionSuccess();
}

std::vector<std::uint32_t> iota(std::size_t n) {
  std::vector<std::uint32_t> v(n);
  std::iota(v.begin(), v.end(), 0u);
  return v;
}

// A poisoned output buffer of n elements and one of slack.
cl::Buffer poisoned(std::size_t n) {
  auto& rt = test::runtime();
  cl::Buffer b(rt.context(), CL_MEM_READ_WRITE, (n + 1) * 4);
  poison(rt.queue(), b);
  return b;
}

void scanCase(std::size_t wg, std::size_t n, std::uint64_t seed) {
  auto& rt = test::runtime();
  auto& q = rt.queue();
  Scanner scanner(rt, gpuOptions(wg));
  checkSettled(scanner.tuning().wg, wg);
  const auto in = makeKeys<std::uint32_t>(n, KeyDist::Random, seed);
  cl::Buffer ib = upload(rt.context(), q, in);
  for (const ScanKind kind : {ScanKind::Exclusive, ScanKind::Inclusive}) {
    cl::Buffer ob = poisoned(n);
    scanner.scan(q, ib, ob, n, kind);
    std::vector<std::uint32_t> want(n);
    if (kind == ScanKind::Exclusive)
      std::exclusive_scan(in.begin(), in.end(), want.begin(), std::uint32_t(0));
    else
      std::inclusive_scan(in.begin(), in.end(), want.begin());
    want.push_back(kPoison);
    EXPECT_TRUE(same(download<std::uint32_t>(q, ob, n + 1), want, kind == ScanKind::Exclusive ? "exclusive" : "inclusive"));
  }
}

void reduceCase(std::size_t wg, std::size_t n, std::uint64_t seed) {
  auto& rt = test::runtime();
  auto& q = rt.queue();
  Reducer reducer(rt, gpuOptions(wg));
  checkSettled(reducer.workGroupSize(), wg);
  const auto in = makeKeys<std::uint32_t>(n, KeyDist::Random, seed);
  cl::Buffer ib = upload(rt.context(), q, in);
  const std::uint32_t mn = n ? *std::min_element(in.begin(), in.end()) : 0xFFFFFFFFu;
  const std::uint32_t mx = n ? *std::max_element(in.begin(), in.end()) : 0u;
  EXPECT_EQ(reducer.reduce<std::uint32_t>(q, ib, n, ReduceOp::Min), mn);
  EXPECT_EQ(reducer.reduce<std::uint32_t>(q, ib, n, ReduceOp::Max), mx);
  EXPECT_EQ(reducer.reduce<std::uint32_t>(q, ib, n, ReduceOp::Sum), std::accumulate(in.begin(), in.end(), 0u));
  // Segments of 100: one work-group per segment.
  const std::size_t seg = 100, segs = (n + seg - 1) / seg;
  cl::Buffer lo = poisoned(segs), hi = poisoned(segs);
  reducer.segmentedMinMaxFixed<std::uint32_t>(q, ib, n, seg, lo, hi);
  const auto got_lo = download<std::uint32_t>(q, lo, segs), got_hi = download<std::uint32_t>(q, hi, segs);
  for (std::size_t s = 0; s < segs; ++s) {
    const auto b = in.begin() + s * seg, e = in.begin() + std::min(n, (s + 1) * seg);
    ASSERT_EQ(got_lo[s], *std::min_element(b, e)) << "segment " << s;
    ASSERT_EQ(got_hi[s], *std::max_element(b, e)) << "segment " << s;
  }
}

void compactCase(std::size_t wg, std::size_t n, std::uint64_t seed) {
  auto& rt = test::runtime();
  auto& q = rt.queue();
  Compactor compactor(rt, gpuOptions(wg));
  checkSettled(compactor.tuning().wg, wg);
  const auto in = makeKeys<std::uint32_t>(n, KeyDist::Random, seed);
  std::mt19937_64 rng(seed ^ 0x5eed);
  std::vector<std::uint32_t> flags(n);
  for (auto& f : flags) f = rng() % 3 == 0 ? static_cast<std::uint32_t>(rng() | 1) : 0u;
  cl::Buffer ib = upload(rt.context(), q, in), fb = upload(rt.context(), q, flags), ob = poisoned(n);
  std::vector<std::uint32_t> want;
  for (std::size_t i = 0; i < n; ++i)
    if (flags[i]) want.push_back(in[i]);
  ASSERT_EQ(compactor.compact(q, ib, fb, ob, n), want.size());
  EXPECT_TRUE(same(download<std::uint32_t>(q, ob, want.size()), want, "compact"));
  EXPECT_EQ(download<std::uint32_t>(q, ob, n + 1)[n], kPoison) << "wrote past n";
  auto sorted = makeKeys<std::uint32_t>(n, KeyDist::FewDistinct, seed + 1);
  std::sort(sorted.begin(), sorted.end());
  cl::Buffer sb = upload(rt.context(), q, sorted), ub = poisoned(n);
  std::vector<std::uint32_t> uniq(sorted.begin(), std::unique(sorted.begin(), sorted.end()));
  ASSERT_EQ(compactor.unique(q, sb, ub, n), uniq.size());
  EXPECT_TRUE(same(download<std::uint32_t>(q, ub, uniq.size()), uniq, "unique"));
}

// Stable: payloads are input indices, so any reordering of equal keys shows.
template <class K>
void radixPairs(RadixSorter& sorter, std::size_t n, KeyDist dist, unsigned key_bits, std::uint64_t seed) {
  auto& rt = test::runtime();
  auto& q = rt.queue();
  const auto keys = makeKeys<K>(n, dist, seed);
  cl::Buffer kb = upload(rt.context(), q, keys, 1), vb = upload(rt.context(), q, iota(n), 1);
  q.enqueueFillBuffer(vb, kPoison, n * 4, 4);
  if constexpr (sizeof(K) == 4)
    sorter.sort(q, kb, &vb, n, key_bits);
  else
    sorter.sort64(q, kb, &vb, n, key_bits);
  const K mask = key_bits >= sizeof(K) * 8 ? ~K(0) : ((K(1) << key_bits) - 1);
  auto order = iota(n);
  std::stable_sort(order.begin(), order.end(), [&](auto a, auto b) { return (keys[a] & mask) < (keys[b] & mask); });
  std::vector<K> want(n);
  for (std::size_t i = 0; i < n; ++i) want[i] = keys[order[i]];
  EXPECT_TRUE(same(download<K>(q, kb, n), want, "keys"));
  order.push_back(kPoison);
  EXPECT_TRUE(same(download<std::uint32_t>(q, vb, n + 1), order, "payload (stability)"));
}

void radixCase(std::size_t wg, std::size_t n, std::uint64_t seed) {
  RadixSorter sorter(test::runtime(), gpuOptions(wg));
  checkSettled(sorter.workGroupSize(false), wg);
  checkSettled(sorter.workGroupSize(true), wg);
  radixPairs<std::uint32_t>(sorter, n, KeyDist::Random, 32, seed);
  radixPairs<std::uint32_t>(sorter, n, KeyDist::FewDistinct, 13, seed + 1);
  radixPairs<std::uint64_t>(sorter, n, KeyDist::Sorted, 64, seed + 2);
}

void bitonicCase(std::size_t wg, std::size_t n, std::uint64_t seed) {
  auto& rt = test::runtime();
  auto& q = rt.queue();
  BitonicSorter sorter(rt, gpuOptions(wg));
  checkSettled(sorter.tuning().wg, wg);
  EXPECT_EQ(sorter.blockSize(), 2 * sorter.tuning().wg);
  const auto keys = makeKeys<std::uint32_t>(n, KeyDist::FewDistinct, seed);
  cl::Buffer kb = upload(rt.context(), q, keys), vb = upload(rt.context(), q, iota(n));
  sorter.sort(q, kb, &vb, n);
  auto want = keys;
  std::sort(want.begin(), want.end());
  const auto got = download<std::uint32_t>(q, kb, n);
  ASSERT_TRUE(same(got, want, "keys"));
  // Not stable, but every payload once and beside its own key.
  const auto vals = download<std::uint32_t>(q, vb, n);
  std::vector<char> seen(n, 0);
  for (std::size_t i = 0; i < n; ++i) {
    ASSERT_LT(vals[i], n) << "payload garbage at " << i;
    ASSERT_FALSE(seen[vals[i]]) << "payload duplicated at " << i;
    seen[vals[i]] = 1;
    ASSERT_EQ(keys[vals[i]], got[i]) << "payload separated from its key at " << i;
  }
}

void segmentedCase(std::size_t wg, std::size_t n, std::uint64_t seed) {
  auto& rt = test::runtime();
  auto& q = rt.queue();
  SegmentedSorter sorter(rt, gpuOptions(wg));
  checkSettled(sorter.tuning().wg, wg);
  // Segments of 0 .. 700 keys: shorter and longer than every group size here.
  std::mt19937_64 rng(seed);
  std::vector<std::uint32_t> offsets{0};
  while (offsets.back() < n) offsets.push_back(std::min<std::uint32_t>(n, offsets.back() + rng() % 701));
  const auto keys = makeKeys<std::uint32_t>(n, KeyDist::Random, seed + 1);
  cl::Buffer kb = upload(rt.context(), q, keys), ob = upload(rt.context(), q, offsets);
  sorter.sort(q, kb, nullptr, n, ob, offsets.size() - 1, nullptr, 700);
  auto want = keys;
  for (std::size_t s = 0; s + 1 < offsets.size(); ++s)
    std::sort(want.begin() + offsets[s], want.begin() + offsets[s + 1]);
  EXPECT_TRUE(same(download<std::uint32_t>(q, kb, n), want, "segments"));
}

using WgParam = std::tuple<Prim, std::size_t>;
class WorkGroupSizeTest : public ::testing::TestWithParam<WgParam> {};

TEST_P(WorkGroupSizeTest, GpuShapeMatchesTwin) {
  const auto [prim, param] = GetParam();
  const std::size_t wg = requestedSize(param);
  const std::uint64_t seed = test::freshSeed();
  SCOPED_TRACE("seed=" + std::to_string(seed) + " work_group_size=" + std::to_string(wg));
  for (const std::size_t n : sizes()) {
    SCOPED_TRACE("n=" + std::to_string(n));
    const std::uint64_t s = seed + n * 7;
    switch (prim) {
      case Prim::Scan: scanCase(wg, n, s); break;
      case Prim::Reduce: reduceCase(wg, n, s); break;
      case Prim::Compact: compactCase(wg, n, s); break;
      case Prim::Radix: radixCase(wg, n, s); break;
      case Prim::Bitonic: bitonicCase(wg, n, s); break;
      case Prim::Segmented: segmentedCase(wg, n, s); break;
    }
    if (HasFailure()) return;  // one broken case is enough to read
  }
}

std::string wgName(const ::testing::TestParamInfo<WgParam>& info) {
  const auto [prim, wg] = info.param;
  return std::string(primName(prim)) + "_" + (wg ? "wg" + std::to_string(wg) : std::string("wgDeviceMax"));
}

INSTANTIATE_TEST_SUITE_P(Compute, WorkGroupSizeTest,
                         ::testing::Combine(::testing::Values(Prim::Scan, Prim::Reduce, Prim::Compact, Prim::Radix,
                                                              Prim::Bitonic, Prim::Segmented),
                                            ::testing::Values(std::size_t(32), std::size_t(64), std::size_t(256),
                                                              std::size_t(0))),
                         wgName);

// Without Options::work_group_size every primitive runs: the default never
// refuses, whatever the kernels allow on this device.
TEST(ComputeWorkGroup, DefaultSizeNeverRefuses) {
  auto& rt = test::runtime();
  const Options gpu{.shape = Shape::GpuWorkGroup};
  EXPECT_NO_THROW({
    RadixSorter radix(rt, gpu);
    checkSettled(radix.workGroupSize(false), 256);
    checkSettled(radix.workGroupSize(true), 256);
    BitonicSorter bitonic(rt, gpu);
    SegmentedSorter segmented(rt, gpu);
    Scanner scanner(rt, gpu);
    Compactor compactor(rt, gpu);
    Reducer reducer(rt, gpu);
    checkSettled(reducer.workGroupSize(), 256);
  });
}

TEST(ComputeWorkGroup, SizeNotAPowerOfTwoOrOverTheDeviceIsRejected) {
  auto& rt = test::runtime();
  EXPECT_THROW({ Scanner s(rt, gpuOptions(48)); }, std::invalid_argument);
  EXPECT_THROW({ RadixSorter s(rt, gpuOptions(rt.info().max_work_group_size * 2)); }, std::invalid_argument);
}

}  // namespace
}  // namespace ml::compute
