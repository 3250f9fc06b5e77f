// compute::Scanner: exclusive / inclusive uint32 scans against std:: on fresh
// random inputs, both kernel shapes, sizes around tile and chunk boundaries.
#include <gtest/gtest.h>

#include <cstdint>
#include <numeric>
#include <random>
#include <string>
#include <tuple>
#include <vector>

#include "host/compute/HostIo.hpp"
#include "host/compute/Scan.hpp"
#include "support/TestDevice.hpp"
#include "support/TestSizes.hpp"

namespace ml::compute {
namespace {

// The last size takes the GPU shape's recursion two levels deep (tiles of
// 1,024); MANYLIGHTS_TEST_SMALL drops it.
std::vector<std::size_t> testSizes() {
  return test::sizesUpToLimit({0, 1, 2, 31, 32, 33, 1023, 1024, 1025, (1u << 20) + 7});
}

std::vector<std::uint32_t> randomValues(std::size_t n, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::vector<std::uint32_t> v(n);
  // Full 32-bit values: the sums wrap, as documented.
  for (auto& x : v) x = static_cast<std::uint32_t>(rng());
  return v;
}

template <class T>
::testing::AssertionResult sameVectors(const std::vector<T>& got, const std::vector<T>& want) {
  if (got.size() != want.size())
    return ::testing::AssertionFailure() << "size " << got.size() << " != " << want.size();
  for (std::size_t i = 0; i < got.size(); ++i)
    if (got[i] != want[i])
      return ::testing::AssertionFailure() << "first mismatch at " << i << " of " << got.size() << ": got " << got[i]
                                           << ", want " << want[i];
  return ::testing::AssertionSuccess();
}

std::vector<std::uint32_t> hostScan(const std::vector<std::uint32_t>& in, ScanKind kind) {
  std::vector<std::uint32_t> want(in.size());
  if (kind == ScanKind::Exclusive)
    std::exclusive_scan(in.begin(), in.end(), want.begin(), std::uint32_t(0));
  else
    std::inclusive_scan(in.begin(), in.end(), want.begin());
  return want;
}

// One test per (shape, kind); the sizes run inside it (CTest starts a
// process per test, so a test per size would cost more in start-up than in
// scanning). Each size gets its own seed derived from the test's.
using ScanParam = std::tuple<Shape, ScanKind>;

class ScanTest : public ::testing::TestWithParam<ScanParam> {};

TEST_P(ScanTest, MatchesStdScan) {
  const auto [shape, kind] = GetParam();
  const std::uint64_t seed = test::freshSeed();
  SCOPED_TRACE("seed=" + std::to_string(seed));
  auto& rt = test::runtime();
  auto& q = rt.queue();
  Scanner scanner(rt, Options{.shape = shape});
  for (const std::size_t n : testSizes()) {
    SCOPED_TRACE("n=" + std::to_string(n));
    const auto in = randomValues(n, seed + n);
    cl::Buffer in_buf = upload(rt.context(), q, in);
    cl::Buffer out_buf(rt.context(), CL_MEM_READ_WRITE, (n + 1) * 4);
    cl::Buffer total_buf(rt.context(), CL_MEM_READ_WRITE, 3 * 4);
    poison(q, out_buf);
    poison(q, total_buf);

    scanner.scan(q, in_buf, out_buf, n, kind, &total_buf, 1);

    auto got = download<std::uint32_t>(q, out_buf, n + 1);
    EXPECT_EQ(got[n], 0xDEADBEEFu) << "wrote past n";
    got.resize(n);
    EXPECT_TRUE(sameVectors(got, hostScan(in, kind)));
    EXPECT_TRUE(sameVectors(download<std::uint32_t>(q, in_buf, n), in)) << "input modified";
    const auto totals = download<std::uint32_t>(q, total_buf, 3);
    EXPECT_EQ(totals[0], 0xDEADBEEFu) << "wrote outside total_index";
    EXPECT_EQ(totals[1], std::accumulate(in.begin(), in.end(), std::uint32_t(0)));
    EXPECT_EQ(totals[2], 0xDEADBEEFu) << "wrote outside total_index";
  }
}

TEST_P(ScanTest, InPlace) {
  const auto [shape, kind] = GetParam();
  const std::uint64_t seed = test::freshSeed();
  SCOPED_TRACE("seed=" + std::to_string(seed));
  auto& rt = test::runtime();
  auto& q = rt.queue();
  Scanner scanner(rt, Options{.shape = shape});
  for (const std::size_t n : testSizes()) {
    SCOPED_TRACE("n=" + std::to_string(n));
    const auto in = randomValues(n, seed ^ n);
    cl::Buffer buf = upload(rt.context(), q, in);
    scanner.scan(q, buf, buf, n, kind);
    EXPECT_TRUE(sameVectors(download<std::uint32_t>(q, buf, n), hostScan(in, kind)));
  }
}

std::string scanName(const ::testing::TestParamInfo<ScanParam>& info) {
  const auto [shape, kind] = info.param;
  return std::string(shape == Shape::CpuChunked ? "Cpu" : "Gpu") +
         (kind == ScanKind::Exclusive ? "_Exclusive" : "_Inclusive");
}

INSTANTIATE_TEST_SUITE_P(Compute, ScanTest,
                         ::testing::Combine(::testing::Values(Shape::CpuChunked, Shape::GpuWorkGroup),
                                            ::testing::Values(ScanKind::Exclusive, ScanKind::Inclusive)),
                         scanName);

TEST(ComputeScan, ExclusiveTotalAndFreeFunctions) {
  const std::uint64_t seed = test::freshSeed();
  SCOPED_TRACE("seed=" + std::to_string(seed));
  auto& rt = test::runtime();
  auto& q = rt.queue();
  const std::size_t n = 5000;
  std::vector<std::uint32_t> in(n);
  std::mt19937 rng(static_cast<std::uint32_t>(seed));
  for (auto& x : in) x = rng() % 1000;
  cl::Buffer in_buf = upload(rt.context(), q, in);
  cl::Buffer out_buf(rt.context(), CL_MEM_READ_WRITE, n * 4);
  poison(q, out_buf);
  Scanner scanner(rt);
  EXPECT_EQ(scanner.exclusiveTotal(q, in_buf, out_buf, n), std::accumulate(in.begin(), in.end(), 0u));

  std::vector<std::uint32_t> want(n);
  poison(q, out_buf);
  exclusive_scan(q, in_buf, out_buf, n);
  std::exclusive_scan(in.begin(), in.end(), want.begin(), 0u);
  EXPECT_TRUE(sameVectors(download<std::uint32_t>(q, out_buf, n), want));
  poison(q, out_buf);
  inclusive_scan(q, in_buf, out_buf, n);
  std::inclusive_scan(in.begin(), in.end(), want.begin());
  EXPECT_TRUE(sameVectors(download<std::uint32_t>(q, out_buf, n), want));
}

TEST(ComputeScan, RejectsShortBuffers) {
  auto& rt = test::runtime();
  Scanner scanner(rt);
  cl::Buffer small(rt.context(), CL_MEM_READ_WRITE, 64);
  EXPECT_THROW(scanner.exclusive(rt.queue(), small, small, 17), std::invalid_argument);
}

}  // namespace
}  // namespace ml::compute
