// The heat map's colour bar (host/util/Heatmap.hpp): the map's pixels are kept
// above it, the bar runs through the palette left to right, and the scale's
// digits are drawn under it and change with the scale; `render --heatmap`
// writes it and prints the scale.
#include <gtest/gtest.h>

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

TEST(HeatmapBar, RenderWritesTheBarAndPrintsTheScale) {
  const std::string file = test::tempDir() + "/heat_bar.png";
  const auto r = test::runManylights("render --size 160x96 --lights 48 --frames 1 --heatmap " + file);
  ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
  EXPECT_NE(r.out.find("heat map scale: 0.."), std::string::npos) << r.out;
  unsigned w = 0, h = 0;
  (void)readImageRgba(file, w, h);
  EXPECT_EQ(w, 160u);
  EXPECT_EQ(h, 96u + colourBarRows(160));
}

}  // namespace
}  // namespace ml
