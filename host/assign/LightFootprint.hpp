#pragma once
// How large the lights are on screen, for techniques that size their tiles or
// clusters by it: a list tested against a cluster much larger than its lights
// holds several times the lights each pixel needs (issue: lists loosen as
// lights shrink), while tiles much smaller than the lights only cost time.
//
// coveringLightPixels(): the projected radius in pixels of the light a covered
// pixel typically sees: the median of r * height / (2 z tan(fovy/2)) over the
// lights in the view, each weighted by its projected area (a light counts in
// as many pixels' lists as it covers). Lights that reach the camera or lie
// outside the view frustum are left out; 0 when none is in view. At most
// kFootprintSamples lights are read, at a fixed stride (the same answer for
// the same lights and camera).
#include <cstddef>
#include <vector>

#include "host/shared/gpu_types.h"

namespace ml {

constexpr std::size_t kFootprintSamples = 1u << 16;

double coveringLightPixels(const std::vector<gpu::PointLight>& lights, const gpu::CameraParams& cam);

// The largest power-of-two tile in [lo, hi] at most `per_radius` times the
// lights' covering radius in pixels; hi when no light is in view.
unsigned tileForLights(double light_pixels, double per_radius, unsigned lo, unsigned hi);

}  // namespace ml
