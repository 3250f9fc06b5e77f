// Clustered forward and clustered deferred render the brute-force image, for
// each unique-cluster method and assignment, and their lists lose no light
// that matters (exact lower bound equality); the GPU kernel shape renders the
// CPU shape's image exactly (the same lists in the same order).
#include <gtest/gtest.h>

#include "gl/FrameRenderer.hpp"
#include "host/run/SceneInputs.hpp"
#include "host/clustered/ClusteredAssigner.hpp"
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
  UniqueMethod unique;
  ClusterAssignMethod assign;
  ClusterBounds bounds = ClusterBounds::Pixels;
  KernelShape shape = KernelShape::Auto;
};
class RenderClustered : public ::testing::TestWithParam<Param> {};

TEST_P(RenderClustered, MatchesBruteForce) {
  test::glContext();
  const auto [pipeline, tile, unique, assign, bounds, shape] = GetParam();
  FrameRenderer r(test::runtime(), scene().scene, kW, kH);
  r.setLights(scene().lights);
  ClusteredAssigner clustered(test::runtime(), tile, unique, assign, bounds, shape);
  const FrameResult res = test::expectBruteForceFrame(r, clustered, pipeline);
  // The map covers exactly the covered pixels, with valid cluster indices.
  const auto map = clustered.readClusterMap();
  std::size_t mapped = 0;
  for (auto c : map)
    if (c != kClusterInvalid) {
      ASSERT_LT(c, clustered.uniqueClusters());
      ++mapped;
    }
  EXPECT_EQ(mapped, res.covered_pixels);
}

// --cluster-tile auto: the tile follows the lights' size on screen frame by
// frame (16 px, the cap below 720 lines, for lights of 130 px on screen; 8 px
// for lights of 20 px), and every frame's lists lose no
// light: brute force's image and lower bound, over the same lights.
TEST(RenderClusteredAuto, TileFollowsTheLightsAndListsStayComplete) {
  test::glContext();
  FrameRenderer r(test::runtime(), scene().scene, kW, kH);
  ClusteredAssigner clustered(test::runtime(), 0, UniqueMethod::PageTable, ClusterAssignMethod::Bvh);
  const auto tiles = test::overThreeLightSizes(r, clustered, Pipeline::Deferred, [&](double px) {
    EXPECT_EQ(clustered.grid().tile_size, autoClusterTile(kW, kH, px));
    EXPECT_DOUBLE_EQ(test::statOf(clustered, "light radius px"), px);
    return clustered.grid().tile_size;
  });
  EXPECT_EQ(tiles, (std::vector<unsigned>{8, 16, 8}));
}

INSTANTIATE_TEST_SUITE_P(
    Clusters, RenderClustered,
    ::testing::Values(Param{Pipeline::Deferred, 32, UniqueMethod::PageTable, ClusterAssignMethod::Bvh},
                      Param{Pipeline::Deferred, 16, UniqueMethod::Sort, ClusterAssignMethod::Brute},
                      Param{Pipeline::Deferred, 32, UniqueMethod::TileSort, ClusterAssignMethod::Bvh},
                      Param{Pipeline::Forward, 32, UniqueMethod::PageTable, ClusterAssignMethod::Bvh},
                      Param{Pipeline::Forward, 64, UniqueMethod::Sort, ClusterAssignMethod::Bvh},
                      Param{Pipeline::Deferred, 32, UniqueMethod::PageTable, ClusterAssignMethod::Bvh,
                            ClusterBounds::Frustum},
                      Param{Pipeline::Forward, 16, UniqueMethod::TileSort, ClusterAssignMethod::Bvh,
                            ClusterBounds::Frustum},
                      Param{Pipeline::Deferred, 32, UniqueMethod::PageTable, ClusterAssignMethod::Bvh,
                            ClusterBounds::Pixels, KernelShape::GpuWorkGroup},
                      Param{Pipeline::Forward, 16, UniqueMethod::Sort, ClusterAssignMethod::Brute,
                            ClusterBounds::Frustum, KernelShape::GpuWorkGroup}),
    [](const auto& info) {
      return std::string(info.param.pipeline == Pipeline::Forward ? "forward" : "deferred") + "_" +
             std::to_string(info.param.tile) + "_" +
             (info.param.unique == UniqueMethod::TileSort ? std::string("tilesort") : uniqueMethodName(info.param.unique)) +
             "_" + clusterAssignName(info.param.assign) + "_" + clusterBoundsName(info.param.bounds) +
             test::shapeSuffix(info.param.shape);
    });

// Both shapes, one frame: the same cluster map, counts and image, exactly.
TEST(RenderClusteredShapes, GpuShapeRendersTheCpuShapesImage) {
  test::glContext();
  FrameRenderer r(test::runtime(), scene().scene, kW, kH);
  r.setLights(scene().lights);
  FrameResult res[2];
  std::vector<float> img[2];
  std::vector<std::uint32_t> map[2];
  for (int s = 0; s < 2; ++s) {
    ClusteredAssigner clustered(test::runtime(), 16, UniqueMethod::TileSort, ClusterAssignMethod::Bvh,
                                ClusterBounds::Pixels, test::kBothShapes[s]);
    res[s] = r.render(scene().cameras.frames.front(), clustered, {Pipeline::Deferred, true});
    img[s] = r.targets().readColor();
    map[s] = clustered.readClusterMap();
  }
  EXPECT_EQ(res[0].light_evaluations, res[1].light_evaluations);
  EXPECT_EQ(res[0].lower_bound, res[1].lower_bound);
  EXPECT_GT(res[0].light_evaluations, 0u);
  EXPECT_EQ(map[0], map[1]);
  const auto diff = test::compareImages(img[1], img[0], 0.0);
  EXPECT_EQ(diff.max_abs, 0.0);
}

TEST(RenderClusteredEdges, OddScreenSizeAndNoLights) {
  test::glContext();
  ClusteredAssigner clustered(test::runtime(), 32, UniqueMethod::PageTable, ClusterAssignMethod::Bvh);
  test::expectNoLightsAtOddSize(clustered);
}

}  // namespace
}  // namespace ml
