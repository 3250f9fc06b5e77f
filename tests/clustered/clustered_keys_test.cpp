// Cluster keys (kernel vs C++ reference, bit for bit) and the three
// unique-cluster methods (page table, radix sort, per-tile sort) against
// std::set of the keys, on random frames and on the page table's edge cases.
// Every test runs in both kernel shapes (the uniquer passes its shape on to
// the scan, compaction and sorts).
#include <gtest/gtest.h>

#include <random>
#include <set>

#include "clustered_support.hpp"
#include "host/clustered/ClusterUniquer.hpp"
#include "support/shape_support.hpp"
#include "support/FpTolerance.hpp"
#include "support/TestDevice.hpp"

namespace ml {
namespace {

constexpr std::uint32_t kPoison = 0xDEADBEEFu;

std::vector<std::uint32_t> deviceKeys(ClusterUniquer& u, const test::ClusterCase& c, const ClusterGrid& g) {
  auto& q = test::runtime().queue();
  cl::Buffer depth(test::runtime().context(), CL_MEM_READ_ONLY, c.depth.size() * 4);
  // Poison: keys of a garbage frame first, then the real one over them.
  std::vector<float> garbage(c.depth.size(), 0.5f);
  q.enqueueWriteBuffer(depth, CL_TRUE, 0, garbage.size() * 4, garbage.data());
  u.keys(q, depth, c.cam(), g);
  q.enqueueWriteBuffer(depth, CL_TRUE, 0, c.depth.size() * 4, c.depth.data());
  u.keys(q, depth, c.cam(), g);
  std::vector<std::uint32_t> keys(c.depth.size());
  q.enqueueReadBuffer(u.keyBuffer(), CL_TRUE, 0, keys.size() * 4, keys.data());
  return keys;
}

class ClusteredKeys : public ::testing::TestWithParam<KernelShape> {};
class ClusteredUnique : public ::testing::TestWithParam<KernelShape> {};

TEST_P(ClusteredKeys, KernelMatchesReference) {
  const std::uint64_t seed = test::freshSeed();
  SCOPED_TRACE("seed=" + std::to_string(seed));
  std::mt19937_64 rng(seed);
  ClusterUniquer u(test::runtime(), UniqueMethod::PageTable, 6, GetParam());
  EXPECT_EQ(u.shape(), GetParam());
  for (auto [w, h, tile] : {std::tuple{160u, 96u, 32u}, std::tuple{203u, 117u, 16u}, std::tuple{7u, 5u, 4u}}) {
    if (test::smallTests() && w > 100) continue;
    SCOPED_TRACE(std::to_string(w) + "x" + std::to_string(h) + " tile " + std::to_string(tile));
    const auto c = test::randomClusterCase(rng, w, h, 0);
    const auto cam = c.cam();
    const ClusterGrid g = ClusterGrid::make(cam, tile);
    const auto ref = referenceKeys(c.depth.data(), cam, g);
    const auto got = deviceKeys(u, c, g);
    // Exact where division and sqrt round correctly, else the stated tolerance.
    ASSERT_TRUE(test::valuesMatch(got, ref, "pixel"));
    std::size_t sky = 0;
    for (std::size_t p = 0; p < ref.size(); ++p) {
      sky += ref[p] == kClusterInvalid;
      if (ref[p] != kClusterInvalid) {
        EXPECT_LT(g.sliceOf(ref[p]), g.slices);
      }
    }
    EXPECT_GT(sky, 0u);
    EXPECT_LT(sky, ref.size());
  }
}

TEST(ClusteredKeysGeometry, SliceFormulaMatchesThesis) {
  // k = floor(log(z / near) / log(1 + 2 tan(theta) / S_y)) away from boundaries.
  gpu::CameraParams cam{};
  cam.width = 1280;
  cam.height = 720;
  cam.near_plane = 0.1f;
  cam.far_plane = 200.0f;
  cam.tan_half_fovy = 0.5773503f;
  const ClusterGrid g = ClusterGrid::make(cam, 32);
  const double q = 1.0 + 2.0 * cam.tan_half_fovy / g.tiles_y;
  for (unsigned k = 0; k + 1 < g.slices; ++k) {
    const float z = float(0.1 * std::pow(q, k + 0.5));
    EXPECT_EQ(sliceOfDepth(z, g), k);
    EXPECT_EQ(unsigned(std::floor(std::log(z / 0.1) / std::log(q))), k);
  }
  EXPECT_GE(g.slice_bounds.back(), cam.far_plane);
  EXPECT_EQ(sliceOfDepth(0.05f, g), 0u);       // in front of near
  EXPECT_EQ(sliceOfDepth(1e9f, g), g.slices - 1);  // beyond far
}

struct UniqueResult {
  std::vector<std::uint32_t> unique, cluster_of;
};

UniqueResult runUnique(ClusterUniquer& u, UniqueMethod m, const ClusterGrid& g) {
  auto& q = test::runtime().queue();
  const std::size_t n = std::size_t(g.width) * g.height;
  u.setMethod(m);
  cl::Buffer uk = u.uniqueKeys(), co = u.clusterOf();
  q.enqueueFillBuffer(uk, kPoison, 0, n * 4);
  q.enqueueFillBuffer(co, kPoison, 0, n * 4);
  const std::uint32_t count = u.unique(q, g);
  UniqueResult r;
  r.unique.resize(count);
  r.cluster_of.resize(n);
  if (count) q.enqueueReadBuffer(uk, CL_TRUE, 0, count * 4, r.unique.data());
  q.enqueueReadBuffer(co, CL_TRUE, 0, n * 4, r.cluster_of.data());
  return r;
}

// All three methods against std::set, and the map back to the clusters.
void checkAllMethods(ClusterUniquer& u, const std::vector<std::uint32_t>& keys, const ClusterGrid& g) {
  const std::set<std::uint32_t> expected_set = [&] {
    std::set<std::uint32_t> s(keys.begin(), keys.end());
    s.erase(kClusterInvalid);
    return s;
  }();
  const std::vector<std::uint32_t> expected(expected_set.begin(), expected_set.end());
  for (UniqueMethod m : {UniqueMethod::PageTable, UniqueMethod::Sort, UniqueMethod::TileSort}) {
    SCOPED_TRACE(uniqueMethodName(m));
    u.setKeys(test::runtime().queue(), keys, g);
    const UniqueResult r = runUnique(u, m, g);
    ASSERT_EQ(r.unique, expected);
    for (std::size_t p = 0; p < keys.size(); ++p) {
      if (keys[p] == kClusterInvalid) {
        ASSERT_EQ(r.cluster_of[p], kClusterInvalid) << "pixel " << p;
      } else {
        ASSERT_LT(r.cluster_of[p], r.unique.size()) << "pixel " << p;
        ASSERT_EQ(r.unique[r.cluster_of[p]], keys[p]) << "pixel " << p;
      }
    }
  }
}

// A synthetic grid (no camera): keys are placed by hand.
ClusterGrid syntheticGrid(unsigned w, unsigned h, unsigned tile, unsigned k_bits) {
  ClusterGrid g;
  g.tile_size = tile;
  g.width = w;
  g.height = h;
  g.tiles_x = (w + tile - 1) / tile;
  g.tiles_y = (h + tile - 1) / tile;
  g.x_bits = bitsFor(g.tiles_x);
  g.y_bits = bitsFor(g.tiles_y);
  g.k_bits = k_bits;
  g.slices = 1u << k_bits;
  return g;
}

TEST_P(ClusteredUnique, ThreeMethodsEqualStdSetOnRandomFrames) {
  const std::uint64_t seed = test::freshSeed();
  SCOPED_TRACE("seed=" + std::to_string(seed));
  std::mt19937_64 rng(seed);
  ClusterUniquer u(test::runtime(), UniqueMethod::PageTable, 6, GetParam());
  for (auto [w, h, tile] : {std::tuple{320u, 180u, 32u}, std::tuple{203u, 117u, 8u}, std::tuple{33u, 65u, 32u}}) {
    if (test::smallTests() && w > 100) continue;
    SCOPED_TRACE(std::to_string(w) + "x" + std::to_string(h) + " tile " + std::to_string(tile));
    const auto c = test::randomClusterCase(rng, w, h, 0);
    const ClusterGrid g = ClusterGrid::make(c.cam(), tile);
    const auto keys = deviceKeys(u, c, g);
    checkAllMethods(u, keys, g);
  }
}

TEST_P(ClusteredUnique, AllPixelsOneCluster) {
  ClusterUniquer u(test::runtime(), UniqueMethod::PageTable, 6, GetParam());
  const ClusterGrid g = syntheticGrid(40, 30, 64, 5);
  checkAllMethods(u, std::vector<std::uint32_t>(40 * 30, g.key(0, 0, 17)), g);
}

TEST_P(ClusteredUnique, EveryPixelADifferentCluster) {
  const std::uint64_t seed = test::freshSeed();
  SCOPED_TRACE("seed=" + std::to_string(seed));
  std::mt19937_64 rng(seed);
  ClusterUniquer u(test::runtime(), UniqueMethod::PageTable, 6, GetParam());
  // 6,144 clusters; 768 under MANYLIGHTS_TEST_SMALL (for Oclgrind).
  const unsigned w = test::smallTests() ? 32u : 96u, h = test::smallTests() ? 24u : 64u;
  const ClusterGrid g = syntheticGrid(w, h, 1, 8);  // one pixel per tile
  std::vector<std::uint32_t> keys(w * h);
  for (unsigned y = 0; y < h; ++y)
    for (unsigned x = 0; x < w; ++x) keys[y * w + x] = g.key(x, y, unsigned(rng() % 256));
  checkAllMethods(u, keys, g);
}

TEST_P(ClusteredUnique, EmptyFrameIsAllSky) {
  ClusterUniquer u(test::runtime(), UniqueMethod::PageTable, 6, GetParam());
  const ClusterGrid g = syntheticGrid(64, 48, 16, 7);
  checkAllMethods(u, std::vector<std::uint32_t>(64 * 48, kClusterInvalid), g);
  // And through the key kernel: sky depth everywhere.
  test::ClusterCase c;
  c.width = 64;
  c.height = 48;
  c.depth.assign(64 * 48, gpu::kSkyDepth);
  const ClusterGrid real = ClusterGrid::make(c.cam(), 16);
  const auto keys = deviceKeys(u, c, real);
  for (auto k : keys) ASSERT_EQ(k, kClusterInvalid);
  checkAllMethods(u, keys, real);
}

TEST_P(ClusteredUnique, KeysAtTheLimitsOfEveryBitField) {
  const std::uint64_t seed = test::freshSeed();
  SCOPED_TRACE("seed=" + std::to_string(seed));
  std::mt19937_64 rng(seed);
  ClusterUniquer u(test::runtime(), UniqueMethod::PageTable, 6, GetParam());
  // 16 x 8 tiles (4 + 3 bits, all values used) and 24 slice bits: 31 bits.
  const ClusterGrid g = syntheticGrid(64, 32, 4, 24);
  ASSERT_EQ(g.keyBits(), 31u);
  const unsigned kmax = (1u << 24) - 1;
  const unsigned ks[] = {0u, 1u, kmax - 1, kmax, 1u << 23, (1u << 23) - 1};
  std::vector<std::uint32_t> keys(64 * 32);
  for (unsigned y = 0; y < 32; ++y)
    for (unsigned x = 0; x < 64; ++x) {
      const auto r = rng();
      keys[y * 64 + x] = r % 11 == 0 ? kClusterInvalid : g.key(x / 4, y / 4, r % 3 == 0 ? unsigned(rng() & kmax) : ks[r % 6]);
    }
  keys[0] = g.key(0, 0, 0);                        // smallest key
  keys[64 * 32 - 1] = g.key(15, 7, kmax);          // largest key: 2^31 - 1
  ASSERT_EQ(keys.back(), 0x7fffffffu);
  checkAllMethods(u, keys, g);
}

TEST(ClusteredUniqueGrid, RejectsKeysWiderThan31Bits) {
  gpu::CameraParams cam{};
  cam.width = 1u << 14;
  cam.height = 1u << 14;
  cam.near_plane = 0.001f;
  cam.far_plane = 1e6f;
  cam.tan_half_fovy = 1.0f;
  EXPECT_ANY_THROW(ClusterGrid::make(cam, 1));
}

INSTANTIATE_TEST_SUITE_P(Shapes, ClusteredKeys, ::testing::ValuesIn(test::kBothShapes),
                         [](const auto& info) { return test::shapeLabel(info.param); });
INSTANTIATE_TEST_SUITE_P(Shapes, ClusteredUnique, ::testing::ValuesIn(test::kBothShapes),
                         [](const auto& info) { return test::shapeLabel(info.param); });

}  // namespace
}  // namespace ml
