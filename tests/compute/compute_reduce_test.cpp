// compute::Reducer: min / max / sum of uint32, int32 and float against std::,
// per-segment min/max (offsets and fixed size), and the per-tile 2D form,
// both kernel shapes.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <random>
#include <string>
#include <tuple>
#include <vector>

#include "host/compute/HostIo.hpp"
#include "host/compute/Reduce.hpp"
#include "support/TestDevice.hpp"
#include "support/TestSizes.hpp"

namespace ml::compute {
namespace {

// MANYLIGHTS_TEST_SMALL drops the last size (see support/TestSizes.hpp).
std::vector<std::size_t> testSizes() {
  return test::sizesUpToLimit({0, 1, 2, 31, 32, 33, 1023, 1024, 1025, (1u << 20) + 7});
}
const auto kShapes = ::testing::Values(Shape::CpuChunked, Shape::GpuWorkGroup);

template <class T>
std::vector<T> randomValues(std::size_t n, std::mt19937_64& rng) {
  std::vector<T> v(n);
  for (auto& x : v) {
    if constexpr (std::is_same_v<T, float>)
      x = std::uniform_real_distribution<float>(-1000.f, 1000.f)(rng);
    else
      x = static_cast<T>(rng());  // full range: sums wrap
  }
  return v;
}

template <class T>
T hostReduce(const std::vector<T>& v, ReduceOp op) {
  switch (op) {
    case ReduceOp::Min: {
      T r = std::is_same_v<T, float> ? std::numeric_limits<T>::infinity() : std::numeric_limits<T>::max();
      for (T x : v) r = std::min(r, x);
      return r;
    }
    case ReduceOp::Max: {
      T r = std::is_same_v<T, float> ? -std::numeric_limits<T>::infinity() : std::numeric_limits<T>::lowest();
      for (T x : v) r = std::max(r, x);
      return r;
    }
    case ReduceOp::Sum: {
      if constexpr (std::is_same_v<T, float>) {
        double s = 0;
        for (T x : v) s += x;
        return static_cast<T>(s);
      } else {
        std::uint32_t s = 0;  // wrapping, as documented
        for (T x : v) s += static_cast<std::uint32_t>(x);
        return static_cast<T>(s);
      }
    }
  }
  return T{};
}

enum class Elem { U32, I32, F32 };
// One test per (shape, element type); the sizes and the three
// operations run inside it (CTest starts a process per test).
using ReduceParam = std::tuple<Shape, Elem>;

template <class T>
void checkReduce(Reducer& reducer, std::size_t n, ReduceOp op, std::uint64_t seed) {
  auto& rt = test::runtime();
  auto& q = rt.queue();
  std::mt19937_64 rng(seed);
  const auto v = randomValues<T>(n, rng);
  cl::Buffer buf = upload(rt.context(), q, v);
  const T want = hostReduce(v, op);
  const T got = reducer.reduce<T>(q, buf, n, op);
  if constexpr (std::is_same_v<T, float>) {
    if (op == ReduceOp::Sum) {
      double abs_sum = 0;
      for (float x : v) abs_sum += std::fabs(x);
      EXPECT_NEAR(got, want, 1e-5 * abs_sum + 1e-3);
    } else {
      EXPECT_EQ(got, want);
    }
  } else {
    EXPECT_EQ(got, want);
  }
  // Async form into a poisoned slot of a larger buffer.
  cl::Buffer out(rt.context(), CL_MEM_READ_WRITE, 12);
  poison(q, out);
  reducer.reduceAsync<T>(q, buf, n, op, out, 1);
  const auto words = download<std::uint32_t>(q, out, 3);
  EXPECT_EQ(words[0], 0xDEADBEEFu);
  EXPECT_EQ(words[2], 0xDEADBEEFu);
  T async_value;
  std::memcpy(&async_value, &words[1], 4);
  EXPECT_EQ(async_value, got);
}

class ReduceTest : public ::testing::TestWithParam<ReduceParam> {};

TEST_P(ReduceTest, MinMaxSumMatchStd) {
  const auto [shape, elem] = GetParam();
  const std::uint64_t seed = test::freshSeed();
  SCOPED_TRACE("seed=" + std::to_string(seed));
  Reducer reducer(test::runtime(), Options{.shape = shape});
  const char* ops[] = {"Min", "Max", "Sum"};
  for (const std::size_t n : testSizes())
    for (ReduceOp op : {ReduceOp::Min, ReduceOp::Max, ReduceOp::Sum}) {
      SCOPED_TRACE("n=" + std::to_string(n) + " op=" + ops[static_cast<int>(op)]);
      const std::uint64_t case_seed = seed + n * 3 + static_cast<std::uint64_t>(op);
      switch (elem) {
        case Elem::U32:
          checkReduce<std::uint32_t>(reducer, n, op, case_seed);
          break;
        case Elem::I32:
          checkReduce<std::int32_t>(reducer, n, op, case_seed);
          break;
        case Elem::F32:
          checkReduce<float>(reducer, n, op, case_seed);
          break;
      }
    }
}

std::string reduceName(const ::testing::TestParamInfo<ReduceParam>& info) {
  const auto [shape, elem] = info.param;
  const char* elems[] = {"U32", "I32", "F32"};
  return std::string(shape == Shape::CpuChunked ? "Cpu" : "Gpu") + "_" + elems[static_cast<int>(elem)];
}

INSTANTIATE_TEST_SUITE_P(Compute, ReduceTest,
                         ::testing::Combine(kShapes, ::testing::Values(Elem::U32, Elem::I32, Elem::F32)),
                         reduceName);

class ReduceShapeTest : public ::testing::TestWithParam<Shape> {};

TEST_P(ReduceShapeTest, ExtremeValues) {
  auto& rt = test::runtime();
  auto& q = rt.queue();
  Reducer reducer(rt, Options{.shape = GetParam()});
  const std::vector<std::uint32_t> ones(3000, 0xFFFFFFFFu);
  cl::Buffer b1 = upload(rt.context(), q, ones);
  EXPECT_EQ(reducer.reduce<std::uint32_t>(q, b1, ones.size(), ReduceOp::Min), 0xFFFFFFFFu);
  EXPECT_EQ(reducer.reduce<std::uint32_t>(q, b1, ones.size(), ReduceOp::Sum), std::uint32_t(0) - 3000u);
  std::vector<std::int32_t> ints(5000, -7);
  ints[4321] = std::numeric_limits<std::int32_t>::min();
  cl::Buffer b2 = upload(rt.context(), q, ints);
  EXPECT_EQ(reducer.reduce<std::int32_t>(q, b2, ints.size(), ReduceOp::Min), std::numeric_limits<std::int32_t>::min());
  EXPECT_EQ(reducer.reduce<std::int32_t>(q, b2, ints.size(), ReduceOp::Max), -7);
  std::vector<float> floats(2000, 0.5f);
  floats[17] = -std::numeric_limits<float>::infinity();
  floats[1999] = std::numeric_limits<float>::infinity();
  cl::Buffer b3 = upload(rt.context(), q, floats);
  EXPECT_EQ(reducer.reduce<float>(q, b3, floats.size(), ReduceOp::Min), -std::numeric_limits<float>::infinity());
  EXPECT_EQ(reducer.reduce<float>(q, b3, floats.size(), ReduceOp::Max), std::numeric_limits<float>::infinity());
  // Empty input: identities.
  EXPECT_EQ(reducer.reduce<float>(q, b3, 0, ReduceOp::Min), std::numeric_limits<float>::infinity());
  EXPECT_EQ(reducer.reduce<std::int32_t>(q, b2, 0, ReduceOp::Max), std::numeric_limits<std::int32_t>::min());
  EXPECT_EQ(reducer.reduce<std::uint32_t>(q, b1, 0, ReduceOp::Sum), 0u);
}

template <class T>
void checkSegments(const std::vector<T>& v, const std::vector<std::uint32_t>& offsets, const std::vector<T>& got_min,
                   const std::vector<T>& got_max) {
  const std::size_t segs = offsets.size() - 1;
  ASSERT_EQ(got_min.size(), segs);
  for (std::size_t s = 0; s < segs; ++s) {
    std::vector<T> part(v.begin() + offsets[s], v.begin() + offsets[s + 1]);
    ASSERT_EQ(got_min[s], hostReduce(part, ReduceOp::Min)) << "segment " << s << " of " << segs;
    ASSERT_EQ(got_max[s], hostReduce(part, ReduceOp::Max)) << "segment " << s << " of " << segs;
  }
}

TEST_P(ReduceShapeTest, SegmentedMinMaxWithOffsets) {
  const std::uint64_t seed = test::freshSeed();
  SCOPED_TRACE("seed=" + std::to_string(seed));
  auto& rt = test::runtime();
  auto& q = rt.queue();
  Reducer reducer(rt, Options{.shape = GetParam()});
  std::mt19937_64 rng(seed);
  // Segment lengths 0..700 (empty ones included) plus one long segment;
  // fewer and shorter under MANYLIGHTS_TEST_SMALL.
  const int nseg = test::smallSizes() ? 12 : 600;
  const std::uint32_t long_len = test::smallSizes() ? 1500 : 50000;
  std::vector<std::uint32_t> offsets{0};
  for (int s = 0; s < nseg; ++s)
    offsets.push_back(offsets.back() + (s == nseg / 2 ? long_len : rng() % 701 * (rng() % 4 != 0)));
  const std::size_t n = offsets.back();
  const std::size_t segs = offsets.size() - 1;
  const auto v = randomValues<float>(n, rng);
  cl::Buffer in = upload(rt.context(), q, v), off = upload(rt.context(), q, offsets);
  cl::Buffer mn(rt.context(), CL_MEM_READ_WRITE, segs * 4), mx(rt.context(), CL_MEM_READ_WRITE, segs * 4);
  poison(q, mn);
  poison(q, mx);
  reducer.segmentedMinMax<float>(q, in, n, off, segs, mn, mx);
  checkSegments(v, offsets, download<float>(q, mn, segs), download<float>(q, mx, segs));

  const auto u = randomValues<std::uint32_t>(n, rng);
  cl::Buffer uin = upload(rt.context(), q, u);
  poison(q, mn);
  poison(q, mx);
  reducer.segmentedMinMax<std::uint32_t>(q, uin, n, off, segs, mn, mx);
  checkSegments(u, offsets, download<std::uint32_t>(q, mn, segs),
                download<std::uint32_t>(q, mx, segs));
}

TEST_P(ReduceShapeTest, SegmentedMinMaxFixedSize) {
  const std::uint64_t seed = test::freshSeed();
  SCOPED_TRACE("seed=" + std::to_string(seed));
  auto& rt = test::runtime();
  auto& q = rt.queue();
  Reducer reducer(rt, Options{.shape = GetParam()});
  std::mt19937_64 rng(seed);
  for (std::size_t n : test::sizesUpToLimit({0u, 1u, 255u, 256u, 257u, 100000u}))
    for (std::size_t size : {1u, 7u, 256u, 4096u}) {
      SCOPED_TRACE("n=" + std::to_string(n) + " segment_size=" + std::to_string(size));
      const auto v = randomValues<std::int32_t>(n, rng);
      const std::size_t segs = (n + size - 1) / size;
      std::vector<std::uint32_t> offsets;
      for (std::size_t s = 0; s <= segs; ++s) offsets.push_back(static_cast<std::uint32_t>(std::min(n, s * size)));
      cl::Buffer in = upload(rt.context(), q, v);
      cl::Buffer mn(rt.context(), CL_MEM_READ_WRITE, (segs + 1) * 4), mx(rt.context(), CL_MEM_READ_WRITE, (segs + 1) * 4);
      poison(q, mn);
      poison(q, mx);
      reducer.segmentedMinMaxFixed<std::int32_t>(q, in, n, size, mn, mx);
      checkSegments(v, offsets, download<std::int32_t>(q, mn, segs), download<std::int32_t>(q, mx, segs));
      EXPECT_EQ(download<std::uint32_t>(q, mn, segs + 1)[segs], 0xDEADBEEFu) << "wrote past the last segment";
    }
}

TEST_P(ReduceShapeTest, TileMinMaxOfDepthImage) {
  const std::uint64_t seed = test::freshSeed();
  SCOPED_TRACE("seed=" + std::to_string(seed));
  auto& rt = test::runtime();
  auto& q = rt.queue();
  Reducer reducer(rt, Options{.shape = GetParam()});
  std::mt19937_64 rng(seed);
  struct Dims {
    std::size_t w, h, tile;
  };
  std::vector<Dims> dims = {{1, 1, 16}, {17, 9, 4}, {33, 65, 32}, {5, 3, 64}};
  if (!test::smallSizes()) dims.push_back({1920, 1080, 16});
  for (const Dims d : dims) {
    SCOPED_TRACE(std::to_string(d.w) + "x" + std::to_string(d.h) + " tile " + std::to_string(d.tile));
    std::vector<float> depth(d.w * d.h);
    for (auto& z : depth) z = std::uniform_real_distribution<float>(0.f, 1.f)(rng);
    const std::size_t tx = (d.w + d.tile - 1) / d.tile, ty = (d.h + d.tile - 1) / d.tile;
    cl::Buffer img = upload(rt.context(), q, depth);
    cl::Buffer mn(rt.context(), CL_MEM_READ_WRITE, tx * ty * 4), mx(rt.context(), CL_MEM_READ_WRITE, tx * ty * 4);
    poison(q, mn);
    poison(q, mx);
    reducer.tileMinMax(q, img, d.w, d.h, d.tile, mn, mx);
    const auto got_min = download<float>(q, mn, tx * ty), got_max = download<float>(q, mx, tx * ty);
    for (std::size_t t = 0; t < tx * ty; ++t) {
      float lo = std::numeric_limits<float>::infinity(), hi = -lo;
      const std::size_t x0 = (t % tx) * d.tile, y0 = (t / tx) * d.tile;
      for (std::size_t y = y0; y < std::min(d.h, y0 + d.tile); ++y)
        for (std::size_t x = x0; x < std::min(d.w, x0 + d.tile); ++x) {
          lo = std::min(lo, depth[y * d.w + x]);
          hi = std::max(hi, depth[y * d.w + x]);
        }
      ASSERT_EQ(got_min[t], lo) << "tile " << t;
      ASSERT_EQ(got_max[t], hi) << "tile " << t;
    }
  }
}

INSTANTIATE_TEST_SUITE_P(Compute, ReduceShapeTest, kShapes,
                         [](const ::testing::TestParamInfo<Shape>& info) {
                           return std::string(info.param == Shape::CpuChunked ? "Cpu" : "Gpu");
                         });

TEST(ComputeReduce, FreeFunctionAndBadArguments) {
  auto& rt = test::runtime();
  auto& q = rt.queue();
  std::vector<std::uint32_t> v = {4, 9, 2, 7};
  cl::Buffer b = upload(rt.context(), q, v);
  EXPECT_EQ(reduce<std::uint32_t>(q, b, v.size(), ReduceOp::Max), 9u);
  EXPECT_EQ(reduce<std::uint32_t>(q, b, v.size(), ReduceOp::Sum), 22u);
  Reducer r(rt);
  EXPECT_THROW(r.reduce<std::uint32_t>(q, b, 5, ReduceOp::Min), std::invalid_argument);
  cl::Buffer small(rt.context(), CL_MEM_READ_WRITE, 4);
  EXPECT_THROW(r.segmentedMinMaxFixed<std::uint32_t>(q, b, 4, 1, small, small), std::invalid_argument);
  EXPECT_THROW(r.tileMinMax(q, b, 2, 2, 0, small, small), std::invalid_argument);
}

}  // namespace
}  // namespace ml::compute
