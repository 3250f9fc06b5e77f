#include "host/util/Heatmap.hpp"

#include <algorithm>
#include <cmath>

namespace ml {

Rgb cubehelix(float t, float start, float rotations, float hue, float gamma) {
  t = std::clamp(t, 0.0f, 1.0f);
  const float pi = 3.14159265358979f;
  const float angle = 2.0f * pi * (start / 3.0f + 1.0f + rotations * t);
  const float l = std::pow(t, gamma);
  const float amp = hue * l * (1.0f - l) / 2.0f;
  const float c = std::cos(angle), s = std::sin(angle);
  return {std::clamp(l + amp * (-0.14861f * c + 1.78277f * s), 0.0f, 1.0f),
          std::clamp(l + amp * (-0.29227f * c - 0.90649f * s), 0.0f, 1.0f),
          std::clamp(l + amp * (1.97294f * c), 0.0f, 1.0f)};
}

std::uint32_t heatmapScaleMax(const std::vector<std::uint32_t>& counts, unsigned stride, unsigned channel,
                              const std::vector<bool>& covered) {
  std::uint32_t max_value = 0;
  for (std::size_t i = 0; i < covered.size(); ++i)
    if (covered[i]) max_value = std::max(max_value, counts[i * stride + channel]);
  return max_value;
}

std::vector<float> heatmapRgba(const std::vector<std::uint32_t>& counts, unsigned stride, unsigned channel,
                               const std::vector<bool>& covered, std::uint32_t max_value) {
  const std::size_t px = covered.size();
  if (max_value == 0) max_value = heatmapScaleMax(counts, stride, channel, covered);
  std::vector<float> out(px * 4, 0.0f);
  for (std::size_t i = 0; i < px; ++i) {
    out[4 * i + 3] = 1.0f;
    if (!covered[i]) continue;
    const float t = max_value ? float(counts[i * stride + channel]) / float(max_value) : 0.0f;
    const Rgb c = cubehelix(t);
    out[4 * i] = c.r;
    out[4 * i + 1] = c.g;
    out[4 * i + 2] = c.b;
  }
  return out;
}

}  // namespace ml
