#include "host/util/Heatmap.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
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

Rgb ratioColour(float t) {
  // Samples of viridis at t = 0, 1/8, ..., 1 (matplotlib's table).
  static constexpr Rgb kSamples[9] = {{0.267004f, 0.004874f, 0.329415f}, {0.282623f, 0.140926f, 0.457517f},
                                      {0.253935f, 0.265254f, 0.529983f}, {0.206756f, 0.371758f, 0.553117f},
                                      {0.163625f, 0.471133f, 0.558148f}, {0.127568f, 0.566949f, 0.550556f},
                                      {0.134692f, 0.658636f, 0.517649f}, {0.477504f, 0.821444f, 0.318195f},
                                      {0.993248f, 0.906157f, 0.143936f}};
  const float x = std::clamp(t, 0.0f, 1.0f) * 8.0f;
  const int i = std::min(int(x), 7);
  const float f = x - float(i);
  const Rgb &a = kSamples[i], &b = kSamples[i + 1];
  return {a.r + (b.r - a.r) * f, a.g + (b.g - a.g) * f, a.b + (b.b - a.b) * f};
}

Rgb heatmapColour(HeatmapKind kind, float t) { return kind == HeatmapKind::Ratio ? ratioColour(t) : cubehelix(t); }

namespace {

// Pixel i's value of `kind`; false where it has none (a ratio over a bound of 0).
bool heatmapValue(const std::vector<std::uint32_t>& counts, std::size_t i, HeatmapKind kind, double& value) {
  const std::uint32_t evaluated = counts[2 * i], bound = counts[2 * i + 1];
  if (kind == HeatmapKind::Ratio) {
    value = bound ? double(evaluated) / double(bound) : 0.0;
    return bound != 0;
  }
  value = kind == HeatmapKind::Evaluated ? evaluated : bound;
  return true;
}

}  // namespace

double heatmapScaleMax(const std::vector<std::uint32_t>& counts, HeatmapKind kind, const std::vector<bool>& covered) {
  double max_value = kind == HeatmapKind::Ratio ? 1.0 : 0.0;
  double v = 0.0;
  for (std::size_t i = 0; i < covered.size(); ++i)
    if (covered[i] && heatmapValue(counts, i, kind, v)) max_value = std::max(max_value, v);
  return max_value;
}

std::vector<float> heatmapRgba(const std::vector<std::uint32_t>& counts, const std::vector<bool>& covered,
                               HeatmapScale scale) {
  const std::size_t px = covered.size();
  if (scale.top == 0) scale.top = heatmapScaleMax(counts, scale.kind, covered);
  const double bottom = scale.kind == HeatmapKind::Ratio ? 1.0 : 0.0;
  std::vector<float> out(px * 4, 0.0f);
  for (std::size_t i = 0; i < px; ++i) {
    out[4 * i + 3] = 1.0f;
    if (!covered[i]) continue;
    double v = 0.0;
    Rgb c = kBoundZeroColour;
    if (heatmapValue(counts, i, scale.kind, v))
      c = heatmapColour(scale.kind, scale.top > bottom ? float((v - bottom) / (scale.top - bottom)) : 0.0f);
    out[4 * i] = c.r;
    out[4 * i + 1] = c.g;
    out[4 * i + 2] = c.b;
  }
  return out;
}

namespace {

// Digits 0-9, '.' and 'x' in a 3x5 pixel font, rows top-down, 3 bits per row
// (MSB left). Drawn by hand: the only text needed is a few numbers, and a
// TrueType renderer (OIIO's render_text over FreeType) would make every heat
// map depend on a font file being installed.
constexpr std::uint16_t kDigits[10] = {
    0b111101101101111, 0b010110010010111, 0b111001111100111, 0b111001111001111, 0b101101111001001,
    0b111100111001111, 0b111100111101111, 0b111001001001001, 0b111101111101111, 0b111101111001111};
constexpr std::uint16_t kPoint = 0b000000000000010, kTimes = 0b000101010101000;

std::uint16_t glyphOf(char c) { return c == '.' ? kPoint : c == 'x' ? kTimes : kDigits[c - '0']; }

unsigned barScale(unsigned width) { return std::max(1u, width / 160); }

// Writes `text` (glyphOf's characters) with its left edge at x0 and its
// glyphs' top row at memory row `top` (rows bottom-up), each font pixel `s` x `s`.
void drawDigits(std::vector<float>& out, unsigned width, const std::string& text, long x0, unsigned top, unsigned s) {
  for (std::size_t i = 0; i < text.size(); ++i) {
    const std::uint16_t glyph = glyphOf(text[i]);
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

// A value of the scale as the bar writes it: counts whole, ratios with up to
// two decimals and an 'x' ("2.5x").
std::string scaleLabel(HeatmapKind kind, double v) {
  if (kind != HeatmapKind::Ratio) return std::to_string(static_cast<unsigned long long>(v));
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.2f", v);
  std::string t = buf;
  while (t.back() == '0') t.pop_back();
  if (t.back() == '.') t.pop_back();
  return t + "x";
}

}  // namespace

// Bottom-up: a margin, the digits, a gap, the bar, a gap, then the map.
unsigned colourBarRows(unsigned width) { return 18 * barScale(width); }

std::vector<float> withColourBar(const std::vector<float>& rgba, unsigned width, unsigned height,
                                 const HeatmapScale& scale) {
  const unsigned s = barScale(width), rows = colourBarRows(width);
  std::vector<float> out(std::size_t(width) * (height + rows) * 4, 0.0f);
  for (std::size_t i = 0; i < std::size_t(width) * rows; ++i) out[4 * i + 3] = 1.0f;
  std::copy(rgba.begin(), rgba.end(), out.begin() + std::ptrdiff_t(std::size_t(width) * rows * 4));
  for (unsigned y = 9 * s; y < 16 * s; ++y)  // the bar
    for (unsigned x = 0; x < width; ++x) {
      const Rgb c = heatmapColour(scale.kind, (float(x) + 0.5f) / float(width));
      float* p = &out[(std::size_t(y) * width + x) * 4];
      p[0] = c.r;
      p[1] = c.g;
      p[2] = c.b;
    }
  const unsigned top = 7 * s - 1;  // the digits' top row, under the bar
  auto text_width = [&](const std::string& t) { return long(t.size() * 4 * s - s); };
  const bool ratio = scale.kind == HeatmapKind::Ratio;
  const double bottom = ratio ? 1.0 : 0.0;
  // Counts label their middle with a whole number, at its place on the bar.
  const double mid_value = ratio ? (bottom + scale.top) / 2 : std::floor(scale.top / 2);
  const std::string lo = scaleLabel(scale.kind, bottom), mid = scaleLabel(scale.kind, mid_value),
                    hi = scaleLabel(scale.kind, scale.top);
  drawDigits(out, width, lo, 0, top, s);
  drawDigits(out, width, hi, long(width) - text_width(hi), top, s);
  const double span = scale.top - bottom;
  const long mid_x = span > 0 ? long((mid_value - bottom) / span * width) - text_width(mid) / 2 : 0;
  if (mid_x > text_width(lo) + long(2 * s) && mid_x + text_width(mid) + long(2 * s) < long(width) - text_width(hi))
    drawDigits(out, width, mid, mid_x, top, s);
  return out;
}

std::vector<float> withColourBar(const std::vector<float>& rgba, unsigned width, unsigned height,
                                 std::uint32_t max_value) {
  return withColourBar(rgba, width, height, {HeatmapKind::Evaluated, double(max_value)});
}

}  // namespace ml
