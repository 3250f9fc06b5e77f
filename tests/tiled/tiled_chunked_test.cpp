// The reworked tile culler (TileCullAlgorithm::ChunkCounts: hoisted per-tile
// math; CPU shape with per-chunk counters instead of atomics) against the C++
// twin (cullTilesReference) and against the previous culler (PairAtomics), in
// both kernel shapes, on fresh random inputs: light counts around the chunk
// boundaries (0, 1, odd, 2^k +- 1), screens of 1 pixel and of odd sizes,
// duplicated lights and extreme radii and distances. One culler serves
// several frames of different sizes, so stale chunk counters or masks from a
// larger frame would show. The CPU shape's lists must also come out in
// ascending light order, exactly as the reference lists them.
#include <gtest/gtest.h>

#include <random>
#include <string>
#include <tuple>
#include <vector>

#include "host/compute/ComputeEnv.hpp"
#include "host/util/Error.hpp"
#include "support/shape_support.hpp"
#include "support/FpTolerance.hpp"
#include "support/TestDevice.hpp"
#include "tiled_support.hpp"

namespace ml {
namespace {

using test::CullCase;
using test::randomCase;

class TiledChunked : public ::testing::TestWithParam<KernelShape> {};

// Lists of the kernel (in its own order for the CPU shape, which promises
// ascending light order; sorted for the GPU shape) against the reference.
void expectMatchesReference(TileLightCuller& culler, const CullCase& c, unsigned tile, TileDepthMode mode) {
  const bool ordered = culler.shape() == KernelShape::CpuChunked;
  const auto got = test::runCuller(culler, c, !ordered);
  const auto ref = test::runReference(c, tile, mode);
  EXPECT_TRUE(test::listsMatch(got, ref, "tile"));
}

TEST_P(TiledChunked, LightCountsAroundChunkBoundariesOnOneCuller) {
  const std::uint64_t seed = test::freshSeed();
  SCOPED_TRACE("seed=" + std::to_string(seed));
  std::mt19937_64 rng(seed);
  for (auto mode : {TileDepthMode::MinMax, TileDepthMode::Mask, TileDepthMode::None}) {
    TileLightCuller culler(test::runtime(), 16, mode, GetParam());
    // Large first, so the later, smaller frames run over stale buffers.
    for (std::size_t n : {1100u, 0u, 1u, 2u, 63u, 64u, 65u, 127u, 129u, 257u, 1025u, 31u}) {
      SCOPED_TRACE(std::string(tileDepthModeName(mode)) + " lights " + std::to_string(n));
      const unsigned w = 33 + unsigned(rng() % 40), h = 17 + unsigned(rng() % 30);
      expectMatchesReference(culler, randomCase(rng, w, h, n), 16, mode);
    }
  }
}

TEST_P(TiledChunked, OnePixelAndOddScreens) {
  const std::uint64_t seed = test::freshSeed();
  SCOPED_TRACE("seed=" + std::to_string(seed));
  std::mt19937_64 rng(seed);
  TileLightCuller culler(test::runtime(), 8, TileDepthMode::MinMax, GetParam());
  for (auto [w, h] : {std::pair{1u, 1u}, std::pair{9u, 1u}, std::pair{1u, 17u}, std::pair{65u, 31u},
                      std::pair{7u, 129u}}) {
    SCOPED_TRACE(std::to_string(w) + "x" + std::to_string(h));
    expectMatchesReference(culler, randomCase(rng, w, h, 200), 8, TileDepthMode::MinMax);
  }
}

// Tile 1 on a 333-pixel-wide screen: light rectangles wider than the columns
// whose side tests the CPU kernel caches (256), so the rest are tested per tile.
TEST_P(TiledChunked, RectanglesWiderThanTheColumnCache) {
  const std::uint64_t seed = test::freshSeed();
  SCOPED_TRACE("seed=" + std::to_string(seed));
  std::mt19937_64 rng(seed);
  for (auto mode : {TileDepthMode::None, TileDepthMode::MinMax, TileDepthMode::Mask}) {
    TileLightCuller culler(test::runtime(), 1, mode, GetParam());
    expectMatchesReference(culler, randomCase(rng, 333, 7, 120), 1, mode);
  }
}

// Tile 1 on a 600-pixel-wide screen: light rectangles spanning more than the
// 64 blocks of 8 x 8 tiles whose depth ranges the CPU kernel keeps per block
// row (the blocks past them are kept untested), and narrow ones that the block
// test skips whole; lists equal the reference in every depth mode. A surface
// across the last 100 columns and a light around the eye that reaches it make
// sure tiles past the 64th block are in some list.
TEST_P(TiledChunked, RectanglesWiderThanTheBlockCache) {
  const std::uint64_t seed = test::freshSeed();
  SCOPED_TRACE("seed=" + std::to_string(seed));
  std::mt19937_64 rng(seed);
  for (auto mode : {TileDepthMode::None, TileDepthMode::MinMax, TileDepthMode::Mask}) {
    SCOPED_TRACE(tileDepthModeName(mode));
    CullCase c = randomCase(rng, 600, 19, 150);
    const glm::mat4 proj = c.camera.projection(float(c.width) / float(c.height));
    for (unsigned y = 0; y < c.height; ++y)
      for (unsigned x = c.width - 100; x < c.width; ++x)
        c.depth[y * c.width + x] = gpu::distance_to_depth(3.0f + 0.01f * float(x % 7), proj[2][2], proj[3][2]);
    c.lights.push_back(makeLight(c.camera.eye, 40.0f, {1, 1, 1}));
    TileLightCuller culler(test::runtime(), 1, mode, GetParam());
    expectMatchesReference(culler, c, 1, mode);
  }
}

// The largest tiles (kMaxTileSize) with depth bounds: the CPU shape's
// one-work-item-per-tile bounds kernel walks 65,536 pixels (twice for the 2.5D
// mask), which passes llvmpipe's loop cap (tests/driver/driver_loop_cap_test.cpp)
// unless a work-group shares each tile there.
TEST_P(TiledChunked, LargestTilesWithDepthBounds) {
  const std::uint64_t seed = test::freshSeed();
  SCOPED_TRACE("seed=" + std::to_string(seed));
  std::mt19937_64 rng(seed);
  for (auto mode : {TileDepthMode::MinMax, TileDepthMode::Mask}) {
    SCOPED_TRACE(tileDepthModeName(mode));
    TileLightCuller culler(test::runtime(), kMaxTileSize, mode, GetParam());
    expectMatchesReference(culler, randomCase(rng, kMaxTileSize + 45, kMaxTileSize + 3, 60), kMaxTileSize, mode);
  }
}

// Tile 1 on a 300 x 200 screen: 60,000 tiles, so a light covering them all
// would pass llvmpipe's loop cap in one work-item of the CPU shape. There
// count() refuses the screen with a UserError instead of giving wrong lists;
// elsewhere the lists are right.
TEST_P(TiledChunked, ScreensPastTheDevicesLoopCapAreRefusedNotWrong) {
  const std::uint64_t seed = test::freshSeed();
  SCOPED_TRACE("seed=" + std::to_string(seed));
  std::mt19937_64 rng(seed);
  const CullCase c = randomCase(rng, 300, 200, 5);
  TileLightCuller culler(test::runtime(), 1, TileDepthMode::None, GetParam());
  const bool capped = compute::resolveTuning(compute::ComputeEnv(test::runtime()), {}).max_chunk != 0;
  if (capped && culler.shape() == KernelShape::CpuChunked) {
    EXPECT_THROW(test::runCuller(culler, c), UserError);
  } else {
    expectMatchesReference(culler, c, 1, TileDepthMode::None);
  }
}

// The same light many times (each index must appear once per tile that it
// reaches), lights of tiny and huge radius, far away and beyond the far plane.
TEST_P(TiledChunked, DuplicatesAndExtremes) {
  const std::uint64_t seed = test::freshSeed();
  SCOPED_TRACE("seed=" + std::to_string(seed));
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  CullCase c = randomCase(rng, 71, 45, 40);
  const glm::mat4 inv_view = glm::inverse(c.camera.view());
  const auto at = [&](float x, float y, float z) { return glm::vec3(inv_view * glm::vec4(x, y, z, 1)); };
  const gpu::PointLight dup = c.lights[std::size_t(rng() % c.lights.size())];
  for (int i = 0; i < 150; ++i) c.lights.push_back(dup);
  for (int i = 0; i < 30; ++i) {
    c.lights.push_back(makeLight(at(u(rng) * 4 - 2, u(rng) * 4 - 2, -1 - u(rng) * 20), 1e-6f, {1, 1, 1}));  // tiny
    c.lights.push_back(makeLight(at(u(rng) * 4 - 2, u(rng) * 4 - 2, -u(rng) * 50), 1e4f, {1, 1, 1}));       // huge
    c.lights.push_back(makeLight(at(u(rng) * 1e5f, u(rng) * 1e5f, -1e5f), 10.0f, {1, 1, 1}));               // far
    c.lights.push_back(makeLight(at(0, 0, -100.0f - 5.0f * u(rng)), 4.0f, {1, 1, 1}));  // straddling the far plane
  }
  for (int i = 0; i < 40; ++i) c.lights.push_back(dup);
  std::shuffle(c.lights.begin(), c.lights.end(), rng);
  for (auto mode : {TileDepthMode::None, TileDepthMode::MinMax, TileDepthMode::Mask}) {
    SCOPED_TRACE(tileDepthModeName(mode));
    TileLightCuller culler(test::runtime(), 8, mode, GetParam());
    expectMatchesReference(culler, c, 8, mode);
  }
}

// The kept previous culler (the benchmark's comparison) gives the same lists.
TEST_P(TiledChunked, SameListsAsThePairAtomicsCuller) {
  const std::uint64_t seed = test::freshSeed();
  SCOPED_TRACE("seed=" + std::to_string(seed));
  std::mt19937_64 rng(seed);
  const CullCase c = randomCase(rng, 97, 61, 700);
  for (auto mode : {TileDepthMode::MinMax, TileDepthMode::Mask}) {
    const auto now = test::runKernel(c, 8, mode, GetParam(), TileCullAlgorithm::ChunkCounts);
    const auto old = test::runKernel(c, 8, mode, GetParam(), TileCullAlgorithm::PairAtomics);
    EXPECT_TRUE(test::listsMatch(now, old, "tile", true));
  }
}

INSTANTIATE_TEST_SUITE_P(Shapes, TiledChunked, ::testing::ValuesIn(test::kBothShapes),
                         [](const auto& info) { return test::shapeLabel(info.param); });

}  // namespace
}  // namespace ml
