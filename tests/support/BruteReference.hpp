#pragma once
// The scene and brute-force reference frames that the technique render tests
// compare against: the default scene with 1,024 generated lights, its first
// camera frame, at kReferenceWidth x kReferenceHeight with counts on. Loaded
// and rendered once per test process (per pipeline), shared by every suite;
// and the checks those suites make of every technique against them.
#include <functional>
#include <string>
#include <vector>

#include "gl/FrameRenderer.hpp"
#include "host/run/SceneInputs.hpp"

namespace ml::test {

constexpr unsigned kReferenceWidth = 320, kReferenceHeight = 180;

const SceneInputs& referenceScene();

struct BruteReference {
  std::vector<float> image;
  FrameResult result;
};
const BruteReference& bruteReference(Pipeline pipeline);

// Renders the reference frame with `assigner` through `r` (the reference
// size, over referenceScene()'s lights) and expects brute force's image
// within 1/255 per channel and 1e-4 on average (lights a list leaves out
// contribute exactly zero, so only the summation order differs), its lower
// bound and covered pixels (lists lose no light in range), and light
// evaluations from the bound up to a quarter of brute force's. Returns the
// frame's result for the technique's own checks.
FrameResult expectBruteForceFrame(FrameRenderer& r, LightAssigner& assigner, Pipeline pipeline);

// The same over `lights` (set on r, brute force rendered first through r):
// brute force's image within 1/255 per channel, its lower bound and covered
// pixels, evaluations from the bound up.
FrameResult expectBruteForceFrameWith(FrameRenderer& r, LightAssigner& assigner, Pipeline pipeline,
                                      const std::vector<gpu::PointLight>& lights);

// One assigner over three frames of the reference lights, their radii scaled
// to about 20, 130 and 20 px on screen (coveringLightPixels of the reference
// frame; larger scales saturate near 130 px, as the near lights then reach
// the camera, which the measure leaves out): each frame checked by
// expectBruteForceFrameWith, then handed to `after_frame` with its light
// pixels, whose results are returned in order.
std::vector<unsigned> overThreeLightSizes(FrameRenderer& r, LightAssigner& assigner, Pipeline pipeline,
                                          const std::function<unsigned(double light_pixels)>& after_frame);

// The value of the assigner's statistic `key` (a test failure and -1 if none).
double statOf(const LightAssigner& assigner, const std::string& key);

// The reference camera at 101 x 37 (a multiple of no tile or cluster size)
// without lights, forward: no light evaluated, pixels still covered.
void expectNoLightsAtOddSize(LightAssigner& assigner);

}  // namespace ml::test
