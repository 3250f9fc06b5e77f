#pragma once
// Heat maps of a counted frame's per-pixel (lights evaluated, lights in range)
// pairs, each with a colour bar that carries its scale:
//  - counts (evaluated, or in range = the exact lower bound): 0..top in the
//    cubehelix palette (Green 2011) with the main thesis's parameters: start
//    0.5, rotations -1.5, hue 1.0, gamma 1.0;
//  - the ratio evaluated / in range: 1x..top in ratioColour (viridis), so a
//    technique's waste reads at a glance (1x: it evaluates only lights that
//    reach the point); pixels whose bound is 0 (no light reaches them) are
//    kBoundZeroColour whatever they evaluate, as no ratio exists there.
// Background pixels (no geometry) stay black.
#include <cstdint>
#include <vector>

namespace ml {

struct Rgb {
  float r, g, b;
};
// t in [0, 1] -> colour.
Rgb cubehelix(float t, float start = 0.5f, float rotations = -1.5f, float hue = 1.0f, float gamma = 1.0f);
// t in [0, 1] -> viridis (matplotlib's), linear between 9 of its samples.
Rgb ratioColour(float t);
inline constexpr Rgb kBoundZeroColour{0.5f, 0.5f, 0.5f};  // grey: viridis has none

enum class HeatmapKind {
  Evaluated,  // lights evaluated per pixel
  Bound,      // lights in range per pixel (the exact lower bound)
  Ratio,      // evaluated / in range
};
// What a colour bar shows: the palette of `kind` from its bottom (0, or 1x
// for ratios) to `top`.
struct HeatmapScale {
  HeatmapKind kind = HeatmapKind::Evaluated;
  double top = 0;
};
Rgb heatmapColour(HeatmapKind kind, float t);  // t in [0, 1] along the bar

// counts: (evaluated, in range) per pixel; `covered` marks pixels with
// geometry. The largest value of `kind` over covered pixels (ratios: over
// pixels with a bound above 0; at least 1): the default top of a scale.
double heatmapScaleMax(const std::vector<std::uint32_t>& counts, HeatmapKind kind,
                       const std::vector<bool>& covered);
// RGBA; a top of 0 is read as heatmapScaleMax.
std::vector<float> heatmapRgba(const std::vector<std::uint32_t>& counts, const std::vector<bool>& covered,
                               HeatmapScale scale);

// A heat map with its scale under it: the palette left to right, and the
// bottom, middle and top of the scale written beneath (white digits; ratios
// as "1x", "2.5x", "4x"), so a reader can tell 5 from 50. `rgba` is `width` x
// `height`, rows bottom-up; the result is `width` x (`height` +
// colourBarRows(width)), the bar rows below the map.
unsigned colourBarRows(unsigned width);
std::vector<float> withColourBar(const std::vector<float>& rgba, unsigned width, unsigned height,
                                 const HeatmapScale& scale);
// A count scale 0..max_value (HeatmapKind::Evaluated).
std::vector<float> withColourBar(const std::vector<float>& rgba, unsigned width, unsigned height,
                                 std::uint32_t max_value);

}  // namespace ml
