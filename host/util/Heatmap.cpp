#include "host/util/Heatmap.hpp"

#include <algorithm>
#include <cmath>
#include <string>

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

namespace {

// Digits 0-9 in a 3x5 pixel font, rows top-down, 3 bits per row (MSB left).
// Drawn by hand: the only text needed is a few numbers, and a TrueType
// renderer (OIIO's render_text over FreeType) would make every heat map
// depend on a font file being installed.
constexpr std::uint16_t kDigits[10] = {
    0b111101101101111, 0b010110010010111, 0b111001111100111, 0b111001111001111, 0b101101111001001,
    0b111100111001111, 0b111100111101111, 0b111001001001001, 0b111101111101111, 0b111101111001111};

unsigned barScale(unsigned width) { return std::max(1u, width / 160); }

// Writes `text` (digits only) with its left edge at x0 and its glyphs' top row
// at memory row `top` (rows bottom-up), each font pixel `s` x `s`.
void drawDigits(std::vector<float>& out, unsigned width, const std::string& text, long x0, unsigned top, unsigned s) {
  for (std::size_t i = 0; i < text.size(); ++i) {
    const std::uint16_t glyph = kDigits[text[i] - '0'];
    for (unsigned gy = 0; gy < 5; ++gy)
      for (unsigned gx = 0; gx < 3; ++gx) {
        if (!((glyph >> (14 - (gy * 3 + gx))) & 1u)) continue;
        for (unsigned dy = 0; dy < s; ++dy)
          for (unsigned dx = 0; dx < s; ++dx) {
            const long x = x0 + long(i * 4 * s + gx * s + dx);
            const unsigned y = top - (gy * s + dy);
            if (x < 0 || x >= long(width)) continue;
            for (int c = 0; c < 3; ++c) out[(std::size_t(y) * width + std::size_t(x)) * 4 + c] = 1.0f;
          }
      }
  }
}

}  // namespace

// Bottom-up: a margin, the digits, a gap, the bar, a gap, then the map.
unsigned colourBarRows(unsigned width) { return 18 * barScale(width); }

std::vector<float> withColourBar(const std::vector<float>& rgba, unsigned width, unsigned height,
                                 std::uint32_t max_value) {
  const unsigned s = barScale(width), rows = colourBarRows(width);
  std::vector<float> out(std::size_t(width) * (height + rows) * 4, 0.0f);
  for (std::size_t i = 0; i < std::size_t(width) * rows; ++i) out[4 * i + 3] = 1.0f;
  std::copy(rgba.begin(), rgba.end(), out.begin() + std::ptrdiff_t(std::size_t(width) * rows * 4));
  for (unsigned y = 9 * s; y < 16 * s; ++y)  // the bar
    for (unsigned x = 0; x < width; ++x) {
      const Rgb c = cubehelix((float(x) + 0.5f) / float(width));
      float* p = &out[(std::size_t(y) * width + x) * 4];
      p[0] = c.r;
      p[1] = c.g;
      p[2] = c.b;
    }
  const unsigned top = 7 * s - 1;  // the digits' top row, under the bar
  auto text_width = [&](const std::string& t) { return long(t.size() * 4 * s - s); };
  const std::string lo = "0", mid = std::to_string(max_value / 2), hi = std::to_string(max_value);
  drawDigits(out, width, lo, 0, top, s);
  drawDigits(out, width, hi, long(width) - text_width(hi), top, s);
  const long mid_x = max_value ? long(double(max_value / 2) / max_value * width) - text_width(mid) / 2 : 0;
  if (mid_x > text_width(lo) + long(2 * s) && mid_x + text_width(mid) + long(2 * s) < long(width) - text_width(hi))
    drawDigits(out, width, mid, mid_x, top, s);
  return out;
}

}  // namespace ml
