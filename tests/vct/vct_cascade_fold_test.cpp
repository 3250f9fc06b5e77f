// Mips across cascade levels (kernels/vct/vct_cascade_fold.cl,
// host/vct/CascadeFold.hpp) against the C++ twin (CascadeFoldTwin.hpp), bit
// for bit, in both kernel shapes, on fresh random volumes (seed printed):
// edges 2..64 (the finer level's edge random too), toroidal and unscrolled
// coarser levels, corners negative and positive, finer windows inside,
// straddling and outside the coarser one (an empty box writes nothing).
// Level 0 of the coarser volume holds random voxels (its own injection), its
// other levels random bits, so every voxel the kernel must leave alone is
// checked too. foldBox is checked against
// counting the cells both windows hold; levels that do not nest are refused.
#include <gtest/gtest.h>

#include <cstring>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include "host/compute/HostIo.hpp"
#include "host/vct/CascadeFold.hpp"
#include "host/vct/CascadeFoldTwin.hpp"
#include "host/vct/VoxelGrid.hpp"
#include "support/SharedBufferIo.hpp"
#include "support/TestDevice.hpp"
#include "support/shape_support.hpp"

namespace ml::vct {
namespace {

using F4 = gpu::ml_float4;

// Premultiplied radiance and opacity: a third empty, a third opaque, the rest partial.
std::vector<F4> randomVoxels(std::mt19937_64& rng, std::size_t n) {
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  std::vector<F4> v(n);
  for (F4& x : v) {
    const unsigned kind = rng() % 3;
    const float a = kind == 0 ? 0.0f : kind == 1 ? 1.0f : u(rng);
    x = {4 * u(rng) * a, 4 * u(rng) * a, 4 * u(rng) * a, a};
  }
  return v;
}

std::vector<F4> randomBits(std::mt19937_64& rng, std::size_t n) {
  std::vector<F4> v(n);
  std::vector<std::uint32_t> w(n * 4);
  for (auto& x : w) x = static_cast<std::uint32_t>(rng());
  if (n) std::memcpy(v.data(), w.data(), n * 16);
  return v;
}

// A random pair of nesting levels: coarse voxel 2 units, fine 1; corners
// within a few windows of each other.
std::pair<gpu::VoxelGridParams, gpu::VoxelGridParams> randomLevels(std::mt19937_64& rng) {
  gpu::VoxelGridParams fine{}, coarse{};
  coarse.edge = 2u << (rng() % 6);
  fine.edge = 2u << (rng() % 6);
  coarse.levels = 1 + static_cast<unsigned>(rng() % log2Exact(coarse.edge));
  fine.levels = 2 + static_cast<unsigned>(rng() % log2Exact(fine.edge));
  fine.wrap = 1;
  coarse.wrap = rng() % 2;
  const long long span = 2 * static_cast<long long>(coarse.edge);
  auto pick = [&](long long n) { return static_cast<long long>(rng() % (2 * n + 1)) - n; };
  const long long kc[3] = {pick(span), pick(span), pick(span)};
  // The fine window's first coarse cell, relative to the coarse corner: a
  // third of the pairs inside (where it fits), a third overlapping, a third anywhere.
  const long long ce = coarse.edge, half = fine.edge / 2, mode = static_cast<long long>(rng() % 3);
  auto offset = [&] {
    if (mode == 0) return static_cast<long long>(rng() % (std::max(0LL, ce - half) + 1));
    if (mode == 1) return -half + 1 + static_cast<long long>(rng() % (ce + half - 1));
    return pick(ce + half + 2);
  };
  long long kf[3];
  for (int a = 0; a < 3; ++a) kf[a] = 2 * (kc[a] + offset());  // even: fine cells nest
  coarse.origin_voxel_size = {2.0f * float(kc[0]), 2.0f * float(kc[1]), 2.0f * float(kc[2]), 2.0f};
  fine.origin_voxel_size = {float(kf[0]), float(kf[1]), float(kf[2]), 1.0f};
  return {fine, coarse};
}

class VctCascadeFold : public ::testing::TestWithParam<KernelShape> {};

TEST_P(VctCascadeFold, MatchesTwinOnRandomLevels) {
  const std::uint64_t seed = test::freshSeed();
  SCOPED_TRACE("seed=" + std::to_string(seed));
  std::mt19937_64 rng(seed);
  auto& rt = test::runtime();
  auto& q = rt.queue();
  CascadeFold fold(compute::ComputeEnv(rt), compute::Options{.shape = GetParam()});
  int inside = 0, partial = 0, missed = 0;
  for (int trial = 0; trial < (test::smallTests() ? 40 : 300); ++trial) {
    SCOPED_TRACE("trial " + std::to_string(trial));
    const auto [fine, coarse] = randomLevels(rng);
    ASSERT_TRUE(foldable(fine, coarse));
    const std::vector<F4> fine_volume = randomVoxels(rng, voxelsAllLevels(fine.edge, fine.levels));
    // Level 0 holds the level's own injection; the levels above it random bits.
    std::vector<F4> coarse_before = randomVoxels(rng, std::size_t(coarse.edge) * coarse.edge * coarse.edge);
    const std::vector<F4> mips = randomBits(rng, voxelsAllLevels(coarse.edge, coarse.levels) - coarse_before.size());
    coarse_before.insert(coarse_before.end(), mips.begin(), mips.end());
    std::vector<F4> want = coarse_before;
    cascadeFoldTwin(fine_volume, fine, want, coarse);
    cl::Buffer f = compute::upload(rt.context(), q, fine_volume), c = compute::upload(rt.context(), q, coarse_before);
    fold.run(q, fine, f, coarse, c);
    const auto got = compute::download<F4>(q, c, want.size());
    ASSERT_EQ(test::firstBitDifference(got, want), want.size())
        << "edges " << fine.edge << " / " << coarse.edge << ", coarse wrap " << coarse.wrap;
    const std::size_t n = foldBox(fine, coarse).voxels();
    const std::size_t fine_cells = std::size_t(fine.edge / 2) * (fine.edge / 2) * (fine.edge / 2);
    (n == 0 ? missed : n == fine_cells ? inside : partial)++;
  }
  std::printf("fine windows inside %d, straddling %d, outside %d\n", inside, partial, missed);
  EXPECT_GT(inside, 0);
  EXPECT_GT(partial, 0);
  EXPECT_GT(missed, 0);
}

INSTANTIATE_TEST_SUITE_P(Shapes, VctCascadeFold, ::testing::ValuesIn(test::kBothShapes),
                         [](const auto& info) { return test::shapeLabel(info.param); });

// foldBox against counting, cell by cell, the coarse cells whose two
// children lie in the fine window.
TEST(VctCascadeFoldBox, IsTheCellsBothWindowsHold) {
  const std::uint64_t seed = test::freshSeed();
  SCOPED_TRACE("seed=" + std::to_string(seed));
  std::mt19937_64 rng(seed);
  for (int trial = 0; trial < 500; ++trial) {
    const auto [fine, coarse] = randomLevels(rng);
    const VoxelBox b = foldBox(fine, coarse);
    const LatticeCorner f = latticeCorner(fine), c = latticeCorner(coarse);
    const long long fc[3] = {f.x, f.y, f.z}, cc[3] = {c.x, c.y, c.z};
    unsigned lo[3], hi[3];
    bool any = true;
    for (int a = 0; a < 3; ++a) {
      lo[a] = coarse.edge;
      hi[a] = 0;
      for (unsigned w = 0; w < coarse.edge; ++w) {
        const long long child = 2 * (cc[a] + w);  // its first fine cell
        if (child >= fc[a] && child + 1 < fc[a] + fine.edge) {
          lo[a] = std::min(lo[a], w);
          hi[a] = std::max(hi[a], w + 1);
        }
      }
      any &= hi[a] > 0;
    }
    if (!any) {
      EXPECT_EQ(b.voxels(), 0u) << "trial " << trial;
      continue;
    }
    for (int a = 0; a < 3; ++a) {
      EXPECT_EQ(b.lo[a], lo[a]) << "trial " << trial << " axis " << a;
      EXPECT_EQ(b.hi[a], hi[a]) << "trial " << trial << " axis " << a;
    }
  }
}

TEST(VctCascadeFoldBox, RefusesLevelsThatDoNotNest) {
  gpu::VoxelGridParams fine{{0, 0, 0, 1}, 8, 2, 1, 0}, coarse{{0, 0, 0, 2}, 8, 1, 0, 0};
  EXPECT_TRUE(foldable(fine, coarse));
  gpu::VoxelGridParams odd = fine;
  odd.origin_voxel_size.x = 1;  // fine corner at an odd lattice cell: its pairs straddle coarse cells
  EXPECT_FALSE(foldable(odd, coarse));
  gpu::VoxelGridParams off = coarse;
  off.origin_voxel_size.y = 0.5f;  // coarse corner off its lattice
  EXPECT_FALSE(foldable(fine, off));
  gpu::VoxelGridParams one = fine;
  one.levels = 1;  // no mip level 1
  EXPECT_FALSE(foldable(one, coarse));
  gpu::VoxelGridParams big = coarse;
  big.origin_voxel_size.w = 4;  // not twice the fine voxel
  EXPECT_FALSE(foldable(fine, big));
  auto& rt = test::runtime();
  CascadeFold fold{compute::ComputeEnv(rt)};
  cl::Buffer f(rt.context(), CL_MEM_READ_WRITE, 4096 * 16), c(rt.context(), CL_MEM_READ_WRITE, 4096 * 16);
  EXPECT_THROW(fold.run(rt.queue(), odd, f, coarse, c), std::invalid_argument);
  cl::Buffer small(rt.context(), CL_MEM_READ_WRITE, 16);
  EXPECT_THROW(fold.run(rt.queue(), fine, small, coarse, c), std::invalid_argument);
}

}  // namespace
}  // namespace ml::vct
