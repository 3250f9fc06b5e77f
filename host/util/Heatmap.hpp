#pragma once
// Heat maps of per-pixel light counts in the cubehelix palette (Green 2011)
// with the main thesis's parameters: start 0.5, rotations -1.5, hue 1.0,
// gamma 1.0. Background pixels (no geometry) stay black.
#include <cstdint>
#include <vector>

namespace ml {

struct Rgb {
  float r, g, b;
};
// t in [0, 1] -> colour.
Rgb cubehelix(float t, float start = 0.5f, float rotations = -1.5f, float hue = 1.0f, float gamma = 1.0f);

// The largest value at `channel` over covered pixels (the default top of the palette).
std::uint32_t heatmapScaleMax(const std::vector<std::uint32_t>& counts, unsigned stride, unsigned channel,
                              const std::vector<bool>& covered);

// counts: `stride` uints per pixel, the value at `channel` is mapped; `covered`
// marks pixels with geometry. max_value 0: the image's maximum. Returns RGBA.
std::vector<float> heatmapRgba(const std::vector<std::uint32_t>& counts, unsigned stride, unsigned channel,
                               const std::vector<bool>& covered, std::uint32_t max_value = 0);

// A heat map with its scale under it: the palette from 0 to `max_value` left
// to right, and 0, max/2 and max written beneath (white digits), so a reader
// can tell 5 from 50. `rgba` is `width` x `height`, rows bottom-up; the result
// is `width` x (`height` + colourBarRows(width)), the bar rows below the map.
unsigned colourBarRows(unsigned width);
std::vector<float> withColourBar(const std::vector<float>& rgba, unsigned width, unsigned height,
                                 std::uint32_t max_value);

}  // namespace ml
