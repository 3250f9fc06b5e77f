// The heat map's colour bar (host/util/Heatmap.hpp): the map's pixels are kept
// above it, the bar runs through the palette left to right, and the scale's
// digits are drawn under it and change with the scale; `render --heatmap`
// writes it and prints the scale. The ratio map's bar runs through its own
// palette with its own scale (1x..top).
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <random>

#include "host/util/Heatmap.hpp"
#include "host/util/ImageIO.hpp"
#include "support/RunCommand.hpp"

namespace ml {
namespace {

std::vector<float> randomMap(std::mt19937& rng, unsigned w, unsigned h) {
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  std::vector<float> m(std::size_t(w) * h * 4);
  for (float& v : m) v = u(rng);
  return m;
}

// White pixels in the digit rows within columns [x0, x1).
std::size_t whiteInLabels(const std::vector<float>& img, unsigned w, unsigned x0, unsigned x1) {
  const unsigned s = colourBarRows(w) / 18;
  std::size_t n = 0;
  for (unsigned y = 2 * s; y < 7 * s; ++y)
    for (unsigned x = x0; x < x1; ++x) n += img[(std::size_t(y) * w + x) * 4] == 1.0f;
  return n;
}

TEST(HeatmapBar, KeepsTheMapAndDrawsThePaletteAndScale) {
  const unsigned seed = std::random_device{}();
  std::printf("seed %u\n", seed);
  std::mt19937 rng(seed);
  for (unsigned w : {1u, 2u, 7u, 63u, 160u, 161u, 319u, 640u, 1023u}) {
    SCOPED_TRACE(w);
    const unsigned h = 1 + rng() % 40, rows = colourBarRows(w), s = rows / 18;
    ASSERT_EQ(rows % 18, 0u);
    const auto map = randomMap(rng, w, h);
    const std::uint32_t top = rng() % 100000;
    const auto out = withColourBar(map, w, h, top);
    ASSERT_EQ(out.size(), std::size_t(w) * (h + rows) * 4);
    EXPECT_TRUE(std::equal(map.begin(), map.end(), out.begin() + std::ptrdiff_t(std::size_t(w) * rows * 4)));
    for (unsigned x = 0; x < w; ++x) {
      const Rgb c = cubehelix((float(x) + 0.5f) / float(w));
      const float* p = &out[(std::size_t(12 * s) * w + x) * 4];
      ASSERT_EQ(p[0], c.r);
      ASSERT_EQ(p[1], c.g);
      ASSERT_EQ(p[2], c.b);
    }
    for (std::size_t i = 0; i < std::size_t(w) * rows; ++i) ASSERT_EQ(out[4 * i + 3], 1.0f);
    if (w >= 3 * s) {
      EXPECT_GT(whiteInLabels(out, w, 0, 3 * s), 0u) << "no '0' at the left";
    }
  }
}

TEST(HeatmapBar, DigitsChangeWithTheScale) {
  const unsigned w = 320, h = 8;
  std::mt19937 rng(std::random_device{}());
  const auto map = randomMap(rng, w, h);
  const auto five = withColourBar(map, w, h, 5), fifty = withColourBar(map, w, h, 50),
             again = withColourBar(map, w, h, 50);
  EXPECT_EQ(fifty, again);
  EXPECT_NE(five, fifty);
  // "50" is wider than "5": more white at the right end.
  EXPECT_GT(whiteInLabels(fifty, w, w - 16, w), whiteInLabels(five, w, w - 16, w));
  EXPECT_GT(whiteInLabels(fifty, w, w / 2 - 8, w / 2 + 8), 0u) << "no middle label (25)";
}

TEST(HeatmapBar, RatioBarUsesItsPaletteAndScale) {
  const unsigned seed = std::random_device{}();
  std::printf("seed %u\n", seed);
  std::mt19937 rng(seed);
  for (unsigned w : {1u, 2u, 63u, 161u, 320u, 1023u}) {
    SCOPED_TRACE(w);
    const unsigned h = 1 + rng() % 20, rows = colourBarRows(w), s = rows / 18;
    const auto map = randomMap(rng, w, h);
    const auto out = withColourBar(map, w, h, {HeatmapKind::Ratio, 1.5 + rng() % 100});
    ASSERT_EQ(out.size(), std::size_t(w) * (h + rows) * 4);
    EXPECT_TRUE(std::equal(map.begin(), map.end(), out.begin() + std::ptrdiff_t(std::size_t(w) * rows * 4)));
    for (unsigned x = 0; x < w; ++x) {
      const Rgb c = ratioColour((float(x) + 0.5f) / float(w));
      const float* p = &out[(std::size_t(12 * s) * w + x) * 4];
      ASSERT_EQ(p[0], c.r);
      ASSERT_EQ(p[1], c.g);
      ASSERT_EQ(p[2], c.b);
    }
  }
  const unsigned w = 320, h = 4;
  const auto map = randomMap(rng, w, h);
  const auto four = withColourBar(map, w, h, {HeatmapKind::Ratio, 4.0}),
             big = withColourBar(map, w, h, {HeatmapKind::Ratio, 40.0});
  EXPECT_NE(four, big);
  // "40x" is wider than "4x"; "1x" stands at the left, "2.5x" in the middle for 4x.
  EXPECT_GT(whiteInLabels(big, w, w - 16, w), whiteInLabels(four, w, w - 16, w));
  EXPECT_GT(whiteInLabels(four, w, 0, 8), 0u);
  EXPECT_GT(whiteInLabels(four, w, w / 2 - 10, w / 2 + 10), 0u) << "no middle label (2.5x)";
  EXPECT_NE(four, withColourBar(map, w, h, 4u)) << "the ratio bar looks like the count bar";
}

// heatmapRgba over random (evaluated, in range) pairs: counts map linearly
// from 0, ratios from 1x, a bound of 0 is grey in the ratio map, sky black.
TEST(HeatmapBar, MapsKnownValuesToThePalette) {
  const unsigned seed = std::random_device{}();
  std::printf("seed %u\n", seed);
  std::mt19937 rng(seed);
  for (std::size_t n : {std::size_t(0), std::size_t(1), std::size_t(17), std::size_t(1025)}) {
    std::vector<std::uint32_t> counts(2 * n);
    std::vector<bool> covered(n);
    for (std::size_t i = 0; i < n; ++i) {
      counts[2 * i + 1] = rng() % 4 == 0 ? 0 : 1 + rng() % 50;
      counts[2 * i] = counts[2 * i + 1] + rng() % 200;
      covered[i] = rng() % 5 != 0;
    }
    const double top = 1.0 + double(1 + rng() % 80) / 8.0;
    const auto ratio = heatmapRgba(counts, covered, {HeatmapKind::Ratio, top});
    const auto evaluated = heatmapRgba(counts, covered, {HeatmapKind::Evaluated, 250.0});
    ASSERT_EQ(ratio.size(), 4 * n);
    for (std::size_t i = 0; i < n; ++i) {
      const double e = counts[2 * i], b = counts[2 * i + 1];
      Rgb want{0, 0, 0}, want_e{0, 0, 0};
      if (covered[i]) {
        want = b == 0 ? kBoundZeroColour : ratioColour(float((e / b - 1.0) / (top - 1.0)));
        want_e = cubehelix(float(e / 250.0));
      }
      EXPECT_EQ(ratio[4 * i], want.r) << i;
      EXPECT_EQ(ratio[4 * i + 1], want.g) << i;
      EXPECT_EQ(ratio[4 * i + 2], want.b) << i;
      EXPECT_EQ(ratio[4 * i + 3], 1.0f);
      EXPECT_EQ(evaluated[4 * i], want_e.r) << i;
      EXPECT_EQ(evaluated[4 * i + 2], want_e.b) << i;
    }
  }
  // The palette's ends: 1x is viridis's first colour, the top and above its last.
  const std::vector<std::uint32_t> ends = {5, 5, 20, 5, 90, 5};
  const auto m = heatmapRgba(ends, {true, true, true}, {HeatmapKind::Ratio, 4.0});
  EXPECT_EQ(m[0], ratioColour(0.0f).r);
  EXPECT_EQ(m[4], ratioColour(1.0f).r);
  EXPECT_EQ(m[8], ratioColour(1.0f).r);
  EXPECT_EQ(heatmapScaleMax(ends, HeatmapKind::Ratio, {true, true, true}), 18.0);
  EXPECT_EQ(heatmapScaleMax(ends, HeatmapKind::Ratio, {true, false, false}), 1.0);
}

TEST(HeatmapBar, RenderWritesTheBarAndPrintsTheScale) {
  const std::string file = test::tempDir() + "/heat_bar.png";
  const auto r = test::runManylights("render --size 160x96 --lights 48 --frames 1 --heatmap " + file);
  ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
  EXPECT_NE(r.out.find("heat map scale: 0.."), std::string::npos) << r.out;
  unsigned w = 0, h = 0;
  (void)readImageRgba(file, w, h);
  EXPECT_EQ(w, 160u);
  EXPECT_EQ(h, 96u + colourBarRows(160));
  const std::string ratio = test::tempDir() + "/ratio_bar.png";
  const auto rr = test::runManylights("render --size 160x96 --lights 48 --frames 1 --ratio-max 2.5 --ratio-map " + ratio);
  ASSERT_EQ(rr.exit_code, 0) << rr.out << rr.err;
  EXPECT_NE(rr.out.find("ratio map scale: 1x..2.5x"), std::string::npos) << rr.out;
  (void)readImageRgba(ratio, w, h);
  EXPECT_EQ(w, 160u);
  EXPECT_EQ(h, 96u + colourBarRows(160));
}

TEST(HeatmapBar, BadRatioFlagsAreOneLine) {
  const std::string dir = test::tempDir();
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"--ratio-max 1 --ratio-map " + dir + "/r.png", "--ratio-max"},
      {"--ratio-max nan --ratio-map " + dir + "/r.png", "--ratio-max"},
      {"--ratio-map " + dir + "/r.txt", "--ratio-map"},
      {"--no-shading --ratio-map " + dir + "/r.png", "--ratio-map"}};
  for (const auto& [flags, named] : cases) {
    SCOPED_TRACE(flags);
    const auto r = test::runManylights("render --size 32x32 --lights 4 --frames 1 " + flags);
    EXPECT_EQ(r.exit_code, 2) << r.out << r.err;
    EXPECT_NE(r.err.find(named), std::string::npos) << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  }
}

}  // namespace
}  // namespace ml
