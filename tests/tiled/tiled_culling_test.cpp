// TileLightCuller (OpenCL) against the C++ reference with the same tests, and
// against the definition: every light whose sphere contains a pixel's surface
// point is in that pixel's tile list. Every test runs in both kernel shapes.
#include <gtest/gtest.h>

#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <random>
#include <tuple>
#include <vector>

#include "host/scene/Camera.hpp"
#include "host/scene/LightSet.hpp"
#include "host/tiled/TileCullerReference.hpp"
#include "host/tiled/TileLightCuller.hpp"
#include "support/shape_support.hpp"
#include "support/FpTolerance.hpp"
#include "support/DepthPoints.hpp"
#include "support/TestDevice.hpp"
#include "tiled_support.hpp"

namespace ml {
namespace {

using test::CullCase;
using test::randomCase;
using test::runKernel;
using test::runReference;

struct Param {
  unsigned tile;
  TileDepthMode mode;
};
class TiledCulling : public ::testing::TestWithParam<std::tuple<Param, KernelShape>> {};

TEST_P(TiledCulling, KernelMatchesReferenceAndIsConservative) {
  const auto [param, shape] = GetParam();
  const auto [tile, mode] = param;
  const std::uint64_t seed = test::freshSeed();
  SCOPED_TRACE("seed=" + std::to_string(seed));
  std::mt19937_64 rng(seed);
  // Sizes that are and are not multiples of the tile size.
  const auto sizes = test::smallTests()
                         ? std::vector<std::tuple<unsigned, unsigned, unsigned>>{{40u, 24u, 60u}, {7u, 5u, 50u}}
                         : std::vector<std::tuple<unsigned, unsigned, unsigned>>{
                               {160u, 96u, 300u}, {203u, 117u, 1000u}, {7u, 5u, 50u}};
  for (auto [w, h, n] : sizes) {
    SCOPED_TRACE(std::to_string(w) + "x" + std::to_string(h) + " lights " + std::to_string(n));
    const CullCase c = randomCase(rng, w, h, n);
    const auto gpu = runKernel(c, tile, mode, shape);
    const auto ref = runReference(c, tile, mode);
    // Exact where division and sqrt round correctly, else the stated tolerance.
    ASSERT_TRUE(test::listsMatch(gpu, ref, "tile"));
    std::size_t total = 0;
    for (const auto& list : gpu) total += list.size();
    EXPECT_GT(total, 0u);
    // Conservative: every light containing a pixel's point is in its tile's list.
    const gpu::CameraParams cam = c.camera.params(w, h);
    TileGrid g{tile, w, h};
    std::size_t checked = 0;
    for (unsigned y = 0; y < h; ++y)
      for (unsigned x = 0; x < w; ++x) {
        const float d = c.depth[y * w + x];
        if (gpu::is_sky_depth(d)) continue;
        const glm::vec3 P = test::pixelWorldPoint(c.camera, cam, x, y, d);
        const auto& list = gpu[(y / tile) * g.tilesX() + x / tile];
        for (std::uint32_t i = 0; i < c.lights.size(); ++i) {
          const auto& l = c.lights[i].position_radius;
          const glm::vec3 dv = glm::vec3(l.x, l.y, l.z) - P;
          if (glm::dot(dv, dv) < l.w * l.w * 0.9999f) {
            ++checked;
            ASSERT_TRUE(std::binary_search(list.begin(), list.end(), i))
                << "light " << i << " reaches pixel (" << x << "," << y << ") but is not in its tile list";
          }
        }
      }
    EXPECT_GT(checked, 0u);
  }
}

INSTANTIATE_TEST_SUITE_P(TileSizesAndModes, TiledCulling,
                         ::testing::Combine(::testing::Values(Param{8, TileDepthMode::MinMax},
                                                              Param{16, TileDepthMode::MinMax},
                                                              Param{32, TileDepthMode::MinMax},
                                                              Param{64, TileDepthMode::MinMax},
                                                              Param{16, TileDepthMode::None},
                                                              Param{16, TileDepthMode::Mask},
                                                              Param{8, TileDepthMode::Mask}),
                                            ::testing::ValuesIn(test::kBothShapes)),
                         [](const auto& info) {
                           const Param p = std::get<0>(info.param);
                           return std::string(tileDepthModeName(p.mode)) + "_" + std::to_string(p.tile) + "_" +
                                  test::shapeLabel(std::get<1>(info.param));
                         });

class TiledCullingEdges : public ::testing::TestWithParam<KernelShape> {};

TEST_P(TiledCullingEdges, ZeroLights) {
  std::mt19937_64 rng(test::freshSeed());
  const CullCase c = randomCase(rng, 100, 60, 0);
  for (const auto& l : runKernel(c, 16, TileDepthMode::MinMax, GetParam())) EXPECT_TRUE(l.empty());
}

// Lights whose rectangles are empty sit between lights with masks: the GPU
// shape finds each mask word's light by binary search over the offsets.
TEST_P(TiledCullingEdges, EmptyRectanglesBetweenLightsWithMasks) {
  const std::uint64_t seed = test::freshSeed();
  SCOPED_TRACE("seed=" + std::to_string(seed));
  std::mt19937_64 rng(seed);
  CullCase c = randomCase(rng, 90, 50, 0);
  // Geometry everywhere at view distance 8, among the lights in front.
  const glm::mat4 proj = c.camera.projection(90.0f / 50.0f);
  std::fill(c.depth.begin(), c.depth.end(), gpu::distance_to_depth(8.0f, proj[2][2], proj[3][2]));
  const glm::mat4 inv_view = glm::inverse(c.camera.view());
  for (int i = 0; i < 200; ++i) {
    const bool behind = rng() % 2 == 0;  // behind the camera: no tile at all
    const glm::vec4 v(float(i % 9) - 4.0f, float(i % 5) - 2.0f, behind ? 3.0f + i : -4.0f - float(i % 13), 1);
    c.lights.push_back(makeLight(glm::vec3(inv_view * v), 0.5f + float(rng() % 40) * 0.1f, {1, 1, 1}));
  }
  for (auto mode : {TileDepthMode::None, TileDepthMode::MinMax}) {
    const auto got = runKernel(c, 8, mode, GetParam());
    const auto ref = runReference(c, 8, mode);
    std::size_t total = 0;
    for (std::size_t t = 0; t < ref.size(); ++t) {
      ASSERT_EQ(got[t], ref[t]) << "tile " << t;
      total += got[t].size();
    }
    EXPECT_GT(total, 0u);
  }
}

TEST_P(TiledCullingEdges, LightsBehindTheCameraReachNoTile) {
  std::mt19937_64 rng(test::freshSeed());
  CullCase c = randomCase(rng, 100, 60, 0);
  const glm::mat4 inv_view = glm::inverse(c.camera.view());
  for (int i = 0; i < 50; ++i)
    c.lights.push_back(makeLight(glm::vec3(inv_view * glm::vec4(float(i % 7) - 3, float(i % 5) - 2, 3.0f + i, 1)), 1.0f,
                                 {1, 1, 1}));
  for (auto mode : {TileDepthMode::None, TileDepthMode::MinMax})
    for (const auto& l : runKernel(c, 16, mode, GetParam())) EXPECT_TRUE(l.empty());
}

TEST_P(TiledCullingEdges, LightContainingTheCameraReachesEveryTileWithGeometryInRange) {
  std::mt19937_64 rng(test::freshSeed());
  CullCase c = randomCase(rng, 64, 64, 0);
  std::fill(c.depth.begin(), c.depth.end(), 0.9f);  // geometry everywhere, close
  c.lights.push_back(makeLight(c.camera.eye, 1000.0f, {1, 1, 1}));
  for (auto mode : {TileDepthMode::None, TileDepthMode::MinMax, TileDepthMode::Mask})
    for (const auto& l : runKernel(c, 16, mode, GetParam())) EXPECT_EQ(l, std::vector<std::uint32_t>{0});
}

// Every light's tile rectangle as the C++ twin computes it (the kernel's
// hit-mask words are a word per 32 tiles of each), among them lights that
// straddle the near plane (every 23rd of the random ones, and 20 beside the
// view): the cube around such a light is cut at the near plane, so those
// beside the view get no rectangle instead of the whole screen.
TEST_P(TiledCullingEdges, RectanglesMatchTheReferenceAndAreCutAtTheNearPlane) {
  const std::uint64_t seed = test::freshSeed();
  SCOPED_TRACE("seed=" + std::to_string(seed));
  std::mt19937_64 rng(seed);
  CullCase c = randomCase(rng, 160, 90, 300);
  const glm::mat4 inv_view = glm::inverse(c.camera.view());
  const std::size_t beside = c.lights.size();
  for (int i = 0; i < 20; ++i) {
    const glm::vec4 v((i % 2 ? 1.0f : -1.0f) * (4.0f + float(i)), float(i % 3) - 1.0f, 0.05f, 1.0f);
    c.lights.push_back(makeLight(glm::vec3(inv_view * v), 0.5f, {1, 1, 1}));
  }
  for (auto mode : {TileDepthMode::None, TileDepthMode::Mask}) {
    TileLightCuller culler(test::runtime(), 8, mode, GetParam());
    const auto got = test::runCuller(culler, c);
    EXPECT_TRUE(test::listsMatch(got, test::runReference(c, 8, mode), "tile"));
    const auto cam = c.cam();
    std::uint64_t words = 0;
    for (std::size_t i = 0; i < c.lights.size(); ++i) {
      const LightTileRect lr = lightTileRect(c.lights[i], cam, culler.tileGrid());
      if (!lr.empty()) words += (std::uint64_t(lr.tx1 - lr.tx0 + 1) * (lr.ty1 - lr.ty0 + 1) + 31) / 32;
      if (i >= beside) {
        EXPECT_TRUE(lr.empty()) << "light " << i << " beside the view got a rectangle";
      }
    }
    EXPECT_EQ(culler.maskWords(), words);
  }
}

TEST_P(TiledCullingEdges, ATileHoldingEveryLight) {
  std::mt19937_64 rng(test::freshSeed());
  CullCase c = randomCase(rng, 48, 48, 0);
  std::fill(c.depth.begin(), c.depth.end(), 0.95f);
  const int n = test::smallTests() ? 300 : 3000;
  for (int i = 0; i < n; ++i) c.lights.push_back(makeLight(c.camera.center, 500.0f + float(i), {1, 0, 0}));
  const auto lists = runKernel(c, 64, TileDepthMode::MinMax, GetParam());  // one tile covers the 48x48 screen
  ASSERT_EQ(lists.size(), 1u);
  EXPECT_EQ(lists[0].size(), std::size_t(n));
}

INSTANTIATE_TEST_SUITE_P(Shapes, TiledCullingEdges, ::testing::ValuesIn(test::kBothShapes),
                         [](const auto& info) { return test::shapeLabel(info.param); });

}  // namespace
}  // namespace ml
