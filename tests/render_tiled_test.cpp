// Tiled forward (forward+) and tiled deferred render the brute-force image,
// for every tile size, and their light lists lose no light that matters; the
// GPU kernel shape renders what the CPU shape renders, with equal counts.
#include <gtest/gtest.h>

#include "gl/FrameRenderer.hpp"
#include "host/app/SceneInputs.hpp"
#include "host/tiled/TiledAssigner.hpp"
#include "shape_support.hpp"
#include "support/BruteReference.hpp"
#include "support/ImageCompare.hpp"
#include "support/TestDevice.hpp"
#include "support/TestGl.hpp"

namespace ml {
namespace {

constexpr unsigned kW = test::kReferenceWidth, kH = test::kReferenceHeight;
using test::bruteReference;
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
  const test::BruteReference& ref = bruteReference(pipeline);
  FrameRenderer r(test::runtime(), scene().scene, kW, kH);
  r.setLights(scene().lights);
  TiledAssigner tiled(test::runtime(), tile, mode, shape);
  FrameResult res = r.render(scene().cameras.frames.front(), tiled, {pipeline, true});
  const auto img = r.targets().readColor();
  // Lights left out contribute exactly zero (attenuation clamps to 0 at d >= r),
  // so only the summation order differs: tolerance mean < 1e-4, max 1/255.
  const auto diff = test::compareImages(img, ref.image, 1.0 / 255.0);
  EXPECT_LT(diff.mean_abs, 1e-4);
  EXPECT_EQ(diff.frac_over_tol, 0.0) << "max diff " << diff.max_abs;
  // Conservative lists: the shader finds every light in range that brute force finds.
  EXPECT_EQ(res.lower_bound, ref.result.lower_bound);
  EXPECT_EQ(res.covered_pixels, ref.result.covered_pixels);
  EXPECT_LT(res.light_evaluations, ref.result.light_evaluations / 4);
  EXPECT_GE(res.light_evaluations, res.lower_bound);
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
  FrameRenderer r(test::runtime(), scene().scene, 101, 37);  // not a multiple of any tile size
  r.setLights({});
  TiledAssigner tiled(test::runtime(), 16, TileDepthMode::MinMax);
  FrameResult res = r.render(scene().cameras.frames.front(), tiled, {Pipeline::Forward, true});
  EXPECT_EQ(res.light_evaluations, 0u);
  EXPECT_GT(res.covered_pixels, 0u);
}

}  // namespace
}  // namespace ml
