// Tiled forward (forward+) and tiled deferred render the brute-force image,
// for every tile size, and their light lists lose no light that matters; the
// GPU kernel shape renders what the CPU shape renders, with equal counts.
#include <gtest/gtest.h>

#include "gl/FrameRenderer.hpp"
#include "host/run/SceneInputs.hpp"
#include "host/tiled/TiledAssigner.hpp"
#include "support/shape_support.hpp"
#include "support/BruteReference.hpp"
#include "support/ImageCompare.hpp"
#include "support/TestDevice.hpp"
#include "support/TestGl.hpp"

namespace ml {
namespace {

constexpr unsigned kW = test::kReferenceWidth, kH = test::kReferenceHeight;
const SceneInputs& scene() { return test::referenceScene(); }

struct Param {
  Pipeline pipeline;
  unsigned tile;
  TileDepthMode mode;
  KernelShape shape = KernelShape::Auto;
};
class RenderTiled : public ::testing::TestWithParam<Param> {};

TEST_P(RenderTiled, MatchesBruteForce) {
  test::glContext();
  const auto [pipeline, tile, mode, shape] = GetParam();
  FrameRenderer r(test::runtime(), scene().scene, kW, kH);
  r.setLights(scene().lights);
  TiledAssigner tiled(test::runtime(), tile, mode, shape);
  const FrameResult res = test::expectBruteForceFrame(r, tiled, pipeline);
  if (mode != TileDepthMode::None && tile <= 16) {
    EXPECT_LE(double(res.light_evaluations), 3.0 * double(res.lower_bound));
  }
}

INSTANTIATE_TEST_SUITE_P(
    Tiles, RenderTiled,
    ::testing::Values(Param{Pipeline::Deferred, 8, TileDepthMode::MinMax}, Param{Pipeline::Deferred, 16, TileDepthMode::MinMax},
                      Param{Pipeline::Deferred, 32, TileDepthMode::MinMax}, Param{Pipeline::Deferred, 64, TileDepthMode::MinMax},
                      Param{Pipeline::Deferred, 16, TileDepthMode::None}, Param{Pipeline::Deferred, 16, TileDepthMode::Mask},
                      Param{Pipeline::Forward, 8, TileDepthMode::MinMax}, Param{Pipeline::Forward, 16, TileDepthMode::MinMax},
                      Param{Pipeline::Forward, 32, TileDepthMode::MinMax}, Param{Pipeline::Forward, 64, TileDepthMode::MinMax},
                      Param{Pipeline::Forward, 16, TileDepthMode::None},
                      Param{Pipeline::Deferred, 16, TileDepthMode::MinMax, KernelShape::GpuWorkGroup},
                      Param{Pipeline::Deferred, 8, TileDepthMode::Mask, KernelShape::GpuWorkGroup},
                      Param{Pipeline::Forward, 32, TileDepthMode::None, KernelShape::GpuWorkGroup}),
    [](const auto& info) {
      return std::string(info.param.pipeline == Pipeline::Forward ? "forward" : "deferred") + "_" +
             tileDepthModeName(info.param.mode) + "_" + std::to_string(info.param.tile) +
             test::shapeSuffix(info.param.shape);
    });

// --tile auto: the tile follows the lights' size on screen frame by frame (16
// px for lights of about 130 px on screen, 8 px for lights of 20 px, the
// culler and the shader switching with it), and every frame's lists lose no
// light: brute force's image and lower bound, over the same lights.
TEST(RenderTiledAuto, TileFollowsTheLightsAndListsStayComplete) {
  test::glContext();
  FrameRenderer r(test::runtime(), scene().scene, kW, kH);
  TiledAssigner tiled(test::runtime(), 0, TileDepthMode::Mask);
  const auto tiles = test::overThreeLightSizes(r, tiled, Pipeline::Deferred, [&](double px) {
    const auto tile = unsigned(test::statOf(tiled, "tile size"));
    EXPECT_EQ(tile, autoTileSize(px));
    return tile;
  });
  EXPECT_EQ(tiles, (std::vector<unsigned>{8, 16, 8}));
}

// Both shapes, one frame: equal counts; images equal up to the order in which
// each tile's lights are summed (the lists' order follows atomics).
TEST(RenderTiledShapes, GpuShapeRendersTheCpuShapesImage) {
  test::glContext();
  FrameRenderer r(test::runtime(), scene().scene, kW, kH);
  r.setLights(scene().lights);
  FrameResult res[2];
  std::vector<float> img[2];
  for (int s = 0; s < 2; ++s) {
    TiledAssigner tiled(test::runtime(), 16, TileDepthMode::Mask, test::kBothShapes[s]);
    res[s] = r.render(scene().cameras.frames.front(), tiled, {Pipeline::Deferred, true});
    img[s] = r.targets().readColor();
  }
  EXPECT_EQ(res[0].light_evaluations, res[1].light_evaluations);
  EXPECT_EQ(res[0].lower_bound, res[1].lower_bound);
  EXPECT_GT(res[0].light_evaluations, 0u);
  const auto diff = test::compareImages(img[1], img[0], 1e-5);
  EXPECT_EQ(diff.frac_over_tol, 0.0) << "max diff " << diff.max_abs;
}

TEST(RenderTiledEdges, OddScreenSizeAndNoLights) {
  test::glContext();
  TiledAssigner tiled(test::runtime(), 16, TileDepthMode::MinMax);
  test::expectNoLightsAtOddSize(tiled);
}

}  // namespace
}  // namespace ml
