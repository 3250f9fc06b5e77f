// --cluster-view: one colour per unique cluster, sky black. The colour map is
// injective over 2^18 cluster indices in 8 bits, and `manylights render
// --cluster-view` writes an image of the frame's size whose distinct colours
// are exactly the unique clusters the run reports, over exactly its covered
// pixels.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <cmath>
#include <fstream>
#include <set>
#include <tuple>

#include "host/clustered/ClusteredAssigner.hpp"
#include "host/util/ImageIO.hpp"
#include "support/RunCommand.hpp"

namespace ml {
namespace {

using Rgb = std::tuple<int, int, int>;

Rgb rgb8(const std::vector<float>& rgba, std::size_t p) {
  auto q = [&](int c) { return int(std::lround(rgba[p * 4 + std::size_t(c)] * 255.0f)); };
  return {q(0), q(1), q(2)};
}

TEST(ClusteredView, ColoursAreDistinctPerClusterAndSkyIsBlack) {
  std::vector<std::uint32_t> map(1u << 18);
  for (std::uint32_t i = 0; i < map.size(); ++i) map[i] = i;
  map.push_back(kClusterInvalid);
  const auto rgba = ClusteredAssigner::clusterViewRgba(map);
  std::set<Rgb> colours;
  for (std::size_t p = 0; p + 1 < map.size(); ++p) {
    const Rgb c = rgb8(rgba, p);
    ASSERT_NE(c, Rgb(0, 0, 0)) << "cluster " << p;
    colours.insert(c);
  }
  EXPECT_EQ(colours.size(), std::size_t(1) << 18);
  EXPECT_EQ(rgb8(rgba, map.size() - 1), Rgb(0, 0, 0));
}

TEST(ClusteredView, CliImageHasOneColourPerUniqueCluster) {
  const std::string dir = test::tempDir();
  const std::string png = dir + "/clusters.png", json = dir + "/clusters.json";
  for (const char* tech : {"clustered-deferred", "clustered-forward"}) {
    SCOPED_TRACE(tech);
    const auto r = test::runManylights(std::string("render --technique ") + tech +
                                       " --lights 64 --size 150x90 --cluster-tile 16 --frames 1 --cluster-view " + png +
                                       " --stats-json " + json);
    ASSERT_EQ(r.exit_code, 0) << r.err << r.out;
    std::ifstream in(json);
    const auto j = nlohmann::json::parse(in);
    const auto clusters = std::size_t(j["technique_stats"]["unique clusters"].get<double>());
    const auto covered = std::size_t(j["covered_pixels"].get<std::uint64_t>());
    unsigned w = 0, h = 0;
    const auto rgba = readImageRgba(png, w, h);
    ASSERT_EQ(w, 150u);
    ASSERT_EQ(h, 90u);
    std::set<Rgb> colours;
    std::size_t coloured = 0;
    for (std::size_t p = 0; p < std::size_t(w) * h; ++p) {
      const Rgb c = rgb8(rgba, p);
      if (c == Rgb(0, 0, 0)) continue;
      ++coloured;
      colours.insert(c);
    }
    EXPECT_GT(clusters, 10u);
    EXPECT_EQ(colours.size(), clusters);
    EXPECT_EQ(coloured, covered);
  }
}

}  // namespace
}  // namespace ml
