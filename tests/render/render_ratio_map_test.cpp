// The evaluations / lower bound map of a counted frame (frameHeatmap with
// HeatmapKind::Ratio, what `render --ratio-map` and the viewer's ratio-map
// view show) on a case whose ratio is known: brute force evaluates all N
// lights at every covered pixel, so its ratio is N / bound, with the bound
// counted here in C++ (boundAtPixel) from the frame's depth.
#include <gtest/gtest.h>

#include <cstdio>

#include "gl/FrameRenderer.hpp"
#include "host/run/SceneInputs.hpp"
#include "host/assign/BruteForceAssigner.hpp"
#include "host/assign/ExactLowerBound.hpp"
#include "host/run/RunLayer.hpp"
#include "support/TestDevice.hpp"
#include "support/TestGl.hpp"

namespace ml {
namespace {

TEST(RatioMap, BruteForceShowsLightsOverTheBound) {
  test::glContext();
  SceneInputArgs args;
  args.lights = "40";
  const SceneInputs in = loadSceneInputs(args);
  const unsigned w = 192, h = 108;
  const double n = double(in.lights.size());
  FrameRenderer r(test::runtime(), in.scene, w, h);
  r.setLights(in.lights);
  const LightGrid grid = buildLightGrid(in.lights);
  for (Pipeline pipeline : {Pipeline::Deferred, Pipeline::Forward}) {
    SCOPED_TRACE(pipeline == Pipeline::Deferred ? "deferred" : "forward");
    std::size_t zero_total = 0;
    for (std::size_t frame = 0; frame < in.cameras.frames.size(); frame += 6) {
      const Camera& cam = in.cameras.frames[frame];
      BruteForceAssigner brute;
      countedRender(r, brute, {pipeline}, cam);
      // The top at N: no ratio is clamped.
      const FrameHeatmap map = frameHeatmap(r, pipeline, {HeatmapKind::Ratio, n});
      ASSERT_EQ(map.rgba.size(), std::size_t(w) * h * 4);
      EXPECT_EQ(map.scale.top, n);
      const auto depth = r.targets().readDepth(pipeline == Pipeline::Deferred);
      const auto counts = r.targets().readCounts();
      const gpu::BoundParams unproject = boundParams(cam.view(), cam.projection(float(w) / h), w, h);
      std::size_t zero = 0, lit = 0, wrong_bound = 0;
      for (unsigned y = 0; y < h; ++y)
        for (unsigned x = 0; x < w; ++x) {
          const std::size_t p = std::size_t(y) * w + x;
          const float* got = &map.rgba[4 * p];
          if (gpu::is_sky_depth(depth[p])) {
            EXPECT_EQ(got[0] + got[1] + got[2], 0.0f);
            continue;
          }
          EXPECT_EQ(counts[2 * p], std::uint32_t(n)) << "brute force evaluates every light";
          const std::uint32_t bound = counts[2 * p + 1];
          wrong_bound += bound != boundAtPixel(grid, unproject, depth[p], x, y);
          const Rgb want = bound == 0 ? kBoundZeroColour : ratioColour(float((n / bound - 1.0) / (n - 1.0)));
          zero += bound == 0;
          lit += bound != 0;
          ASSERT_EQ(got[0], want.r) << x << "," << y << " bound " << bound;
          ASSERT_EQ(got[1], want.g) << x << "," << y << " bound " << bound;
          ASSERT_EQ(got[2], want.b) << x << "," << y << " bound " << bound;
        }
      EXPECT_EQ(wrong_bound, 0u);
      EXPECT_GT(lit, 0u) << "frame " << frame;
      zero_total += zero;
    }
    EXPECT_GT(zero_total, 0u) << "no pixel without a light in range: the grey is untested";
  }
}

}  // namespace
}  // namespace ml
