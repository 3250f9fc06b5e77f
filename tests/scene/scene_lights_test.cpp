// Light sets: seeded generation in weighted boxes, JSON load/save (manylights
// and nTiled formats), validation, and the shipped default light set.
#include "ml_test_paths.h"  // MANYLIGHTS_TEST_DATA_DIR, MANYLIGHTS_BINARY (generated)
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "host/scene/LightSet.hpp"
#include "host/util/Error.hpp"
#include "support/FileErrors.hpp"
#include "support/TempDir.hpp"
#include "support/TestDevice.hpp"

namespace {

namespace fs = std::filesystem;

using ml::test::TempDir;

glm::vec3 pos(const ml::gpu::PointLight& l) { return {l.position_radius.x, l.position_radius.y, l.position_radius.z}; }
glm::vec3 col(const ml::gpu::PointLight& l) { return {l.color.x, l.color.y, l.color.z}; }

bool sameBits(const std::vector<ml::gpu::PointLight>& a, const std::vector<ml::gpu::PointLight>& b) {
  return a.size() == b.size() && (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof a[0]) == 0);
}

bool inBox(glm::vec3 p, const ml::LightVolume& v) {
  return glm::all(glm::greaterThanEqual(p, v.min)) && glm::all(glm::lessThanEqual(p, v.max));
}

TEST(LightGenerate, DeterministicPerSeed) {
  const std::uint64_t seed = ml::test::freshSeed();
  SCOPED_TRACE("seed " + std::to_string(seed));
  const std::vector<ml::LightVolume> boxes = {{{-1, -1, -1}, {1, 1, 1}, 1.0f}, {{5, 0, 0}, {9, 2, 3}, 3.0f}};
  ml::LightGenParams p;
  p.count = 500;
  p.radius = 2.0f;
  p.radius_jitter = 0.25f;
  p.seed = seed;
  const auto a = ml::generateLights(boxes, p);
  const auto b = ml::generateLights(boxes, p);
  ASSERT_EQ(a.size(), 500u);
  EXPECT_TRUE(sameBits(a, b));
  p.seed = seed + 1;
  const auto c = ml::generateLights(boxes, p);
  ASSERT_EQ(c.size(), 500u);
  EXPECT_FALSE(sameBits(a, c));
  // A longer run with the same seed starts with the same lights.
  p.seed = seed;
  p.count = 700;
  const auto d = ml::generateLights(boxes, p);
  EXPECT_TRUE(std::equal(a.begin(), a.end(), d.begin(), [](auto& x, auto& y) { return std::memcmp(&x, &y, sizeof x) == 0; }));
  p.count = 0;
  EXPECT_TRUE(ml::generateLights(boxes, p).empty());
}

TEST(LightGenerate, InsideBoxesWithWeightedShares) {
  const std::uint64_t seed = ml::test::freshSeed();
  SCOPED_TRACE("seed " + std::to_string(seed));
  // Weights deliberately unrelated to the box volumes (1, 8, 27, 64), and one
  // zero-weight box that must stay empty.
  const std::vector<ml::LightVolume> boxes = {
      {{0, 0, 0}, {1, 1, 1}, 5.0f},
      {{10, 0, 0}, {12, 2, 2}, 2.0f},
      {{20, 0, 0}, {23, 3, 3}, 0.0f},
      {{30, -4, -4}, {34, 0, 0}, 1.0f},
  };
  ml::LightGenParams p;
  p.count = 40000;
  p.radius = 3.0f;
  p.radius_jitter = 0.5f;
  p.seed = seed;
  const auto lights = ml::generateLights(boxes, p);
  ASSERT_EQ(lights.size(), p.count);

  std::vector<std::size_t> hits(boxes.size(), 0);
  std::vector<glm::dvec3> mean(boxes.size(), glm::dvec3(0.0));
  float rmin = 1e30f, rmax = 0.0f;
  int sectors[6] = {};
  double middle_sum = 0.0;  // the channel that is neither 0 nor 1; uniform in [0, 1] for a uniform hue
  for (const auto& l : lights) {
    int which = -1;
    for (std::size_t b = 0; b < boxes.size(); ++b)
      if (inBox(pos(l), boxes[b])) which = int(b);
    ASSERT_GE(which, 0) << "light outside every box";
    ++hits[std::size_t(which)];
    const auto& box = boxes[std::size_t(which)];
    mean[std::size_t(which)] += glm::dvec3((pos(l) - box.min) / (box.max - box.min));

    const float r = l.position_radius.w;
    ASSERT_GE(r, 1.5f);
    ASSERT_LE(r, 4.5f);
    rmin = std::min(rmin, r);
    rmax = std::max(rmax, r);

    // Fully saturated, full value: one channel at 1, one at 0.
    const glm::vec3 c = col(l);
    ASSERT_FLOAT_EQ(std::max({c.r, c.g, c.b}), 1.0f);
    ASSERT_FLOAT_EQ(std::min({c.r, c.g, c.b}), 0.0f);
    // Hue sector from the channel order, to see that all hues occur.
    const int sector = c.r == 1.0f ? (c.b == 0.0f ? 0 : 5) : c.g == 1.0f ? (c.b == 0.0f ? 1 : 2) : (c.r == 0.0f ? 3 : 4);
    ++sectors[sector];
    middle_sum += c.r + c.g + c.b - 1.0;
  }
  EXPECT_EQ(hits[2], 0u);
  const double total_weight = 8.0;
  for (std::size_t b = 0; b < boxes.size(); ++b) {
    const double share = boxes[b].weight / total_weight;
    const double expect = share * p.count;
    const double sigma = std::sqrt(p.count * share * (1 - share));
    EXPECT_NEAR(double(hits[b]), expect, 5 * sigma + 1) << "box " << b;
    if (hits[b] > 100) {
      // Uniform placement: the normalised mean position is the box centre.
      const glm::dvec3 m = mean[b] / double(hits[b]);
      const double tol = 5.0 / std::sqrt(12.0 * double(hits[b]));
      for (int a = 0; a < 3; ++a) EXPECT_NEAR(m[a], 0.5, tol) << "box " << b << " axis " << a;
    }
  }
  for (int s = 0; s < 6; ++s) EXPECT_NEAR(sectors[s], p.count / 6.0, 5 * std::sqrt(p.count / 6.0)) << "sector " << s;
  EXPECT_NEAR(middle_sum / p.count, 0.5, 5 * std::sqrt(1.0 / 12.0 / p.count));
  EXPECT_LT(rmin, 1.55f);  // jitter spans the whole [r(1-j), r(1+j)] range
  EXPECT_GT(rmax, 4.45f);
}

TEST(LightGenerate, RejectsUnusableInput) {
  ml::LightGenParams p;
  p.count = 10;
  EXPECT_THROW(ml::generateLights({}, p), ml::UserError);
  EXPECT_THROW(ml::generateLights({{{0, 0, 0}, {1, 1, 1}, 0.0f}}, p), ml::UserError);
  EXPECT_THROW(ml::generateLights({{{0, 0, 0}, {-1, 1, 1}, 1.0f}}, p), ml::UserError);
  EXPECT_THROW(ml::generateLights({{{0, 0, 0}, {1, 1, 1}, -1.0f}}, p), ml::UserError);
  p.radius = 0.0f;
  EXPECT_THROW(ml::generateLights({{{0, 0, 0}, {1, 1, 1}, 1.0f}}, p), ml::UserError);
  p.radius = 1.0f;
  p.radius_jitter = 1.0f;
  EXPECT_THROW(ml::generateLights({{{0, 0, 0}, {1, 1, 1}, 1.0f}}, p), ml::UserError);
  // A degenerate (flat) box is fine: lights on a plane.
  p.radius_jitter = 0.0f;
  const auto flat = ml::generateLights({{{0, 2, 0}, {4, 2, 4}, 1.0f}}, p);
  for (const auto& l : flat) EXPECT_EQ(l.position_radius.y, 2.0f);
}

TEST(LightJson, RoundTripIsBitExact) {
  const std::uint64_t seed = ml::test::freshSeed();
  SCOPED_TRACE("seed " + std::to_string(seed));
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<float> any(-1e4f, 1e4f), unit(0.0f, 1.0f), radius(1e-3f, 1e3f);
  std::vector<ml::gpu::PointLight> lights;
  for (int i = 0; i < 300; ++i)
    lights.push_back(ml::makeLight({any(rng), any(rng) * 1e-3f, any(rng) * 1e-6f}, radius(rng), {unit(rng), unit(rng), unit(rng)}));
  // Values without a short decimal form, and ones that have one.
  lights.push_back(ml::makeLight({0.1f, 1.0f / 3.0f, 16777217.0f}, std::nextafter(1.0f, 2.0f), {0.0f, 1.0f, 1e-7f}));
  lights.push_back(ml::makeLight({-0.0f, std::numeric_limits<float>::denorm_min(), 3.4e38f}, 1e-30f, {1.0f, 0.5f, 0.25f}));

  TempDir dir;
  const std::string path = dir.file("lights.json");
  ml::saveLightsJson(path, lights);
  const auto loaded = ml::loadLightsJson(path);
  ASSERT_EQ(loaded.size(), lights.size());
  for (std::size_t i = 0; i < lights.size(); ++i) {
    for (int k = 0; k < 3; ++k) {
      EXPECT_EQ(pos(loaded[i])[k], pos(lights[i])[k]) << "light " << i;
      EXPECT_EQ(col(loaded[i])[k], col(lights[i])[k]) << "light " << i;
    }
    EXPECT_EQ(loaded[i].position_radius.w, lights[i].position_radius.w) << "light " << i;
  }

  // The file is the documented manylights format.
  std::ifstream in(path);
  const auto doc = nlohmann::json::parse(in);
  ASSERT_TRUE(doc.at("lights").is_array());
  const auto& first = doc["lights"][0];
  EXPECT_TRUE(first.at("position").is_array());
  EXPECT_EQ(first["position"].size(), 3u);
  EXPECT_TRUE(first.at("intensity").is_array());
  EXPECT_TRUE(first.at("radius").is_number());

  ml::saveLightsJson(path, {});
  EXPECT_TRUE(ml::loadLightsJson(path).empty());
}

TEST(LightJson, LoadsNTiledSuiteFormat) {
  // Shape of the nTiled thesis suite's light files: vectors and colours as
  // objects, keys in arbitrary order.
  TempDir dir;
  const std::string path = dir.write("1260#2x_3y_3z.json", R"({
  "lights": [
    {
      "intensity": {"b": 0.0, "r": 1.0, "g": 0.10206226170791333},
      "position": {"z": -18.963894844055176, "y": 4.289805218577385, "x": 81.6195576985677},
      "radius": 23.0
    },
    {
      "intensity": {"b": 0.25, "r": 0.0, "g": 1.0},
      "position": {"z": -26.5, "y": 4.25, "x": 80.0},
      "radius": 7
    }
  ]
})");
  const auto lights = ml::loadLightsJson(path);
  ASSERT_EQ(lights.size(), 2u);
  // JSON numbers are doubles, narrowed to float afterwards. That is not always
  // the float nearest to the decimal text: -18.963894844055176 lies just past a
  // float midpoint that its double lands on exactly, so write the expectation
  // as the narrowed double, not as a float literal.
  auto f = [](double d) { return static_cast<float>(d); };
  EXPECT_EQ(pos(lights[0]), glm::vec3(f(81.6195576985677), f(4.289805218577385), f(-18.963894844055176)));
  EXPECT_EQ(col(lights[0]), glm::vec3(1.0f, f(0.10206226170791333), 0.0f));
  EXPECT_EQ(lights[0].position_radius.w, 23.0f);
  EXPECT_EQ(pos(lights[1]), glm::vec3(80.0f, 4.25f, -26.5f));
  EXPECT_EQ(col(lights[1]), glm::vec3(0.0f, 1.0f, 0.25f));
  EXPECT_EQ(lights[1].position_radius.w, 7.0f);
}

void expectLightError(const std::string& path, const std::string& also) {
  ml::test::expectFileError([&] { (void)ml::loadLightsJson(path); }, path, also);
}

TEST(LightJson, ErrorsNameFileAndLight) {
  TempDir dir;
  expectLightError(dir.file("missing.json"), "cannot open");
  expectLightError(dir.write("syntax.json", "{\"lights\": [ {\"position\": [1,2,3],\n"), "JSON");
  expectLightError(dir.write("array.json", "[]"), "lights");
  expectLightError(dir.write("nolights.json", "{\"light\": []}"), "lights");
  expectLightError(dir.write("notarray.json", "{\"lights\": 3}"), "lights");

  const std::string good = R"({"position": [0, 0, 0], "radius": 1, "intensity": [1, 1, 1]})";
  auto second = [&](const std::string& name, const std::string& bad, const std::string& also) {
    SCOPED_TRACE(name);
    const std::string path = dir.write(name, "{\"lights\": [" + good + ",\n " + bad + "]}");
    expectLightError(path, "light 1");
    expectLightError(path, also);
  };
  second("r0.json", R"({"position": [0, 0, 0], "radius": 0, "intensity": [1, 1, 1]})", "radius");
  second("rneg.json", R"({"position": [0, 0, 0], "radius": -2.5, "intensity": [1, 1, 1]})", "radius");
  second("rstr.json", R"({"position": [0, 0, 0], "radius": "big", "intensity": [1, 1, 1]})", "radius");
  second("rmissing.json", R"({"position": [0, 0, 0], "intensity": [1, 1, 1]})", "radius");
  second("rhuge.json", R"({"position": [0, 0, 0], "radius": 1e39, "intensity": [1, 1, 1]})", "finite");
  second("p2.json", R"({"position": [0, 0], "radius": 1, "intensity": [1, 1, 1]})", "position");
  second("p4.json", R"({"position": [0, 0, 0, 1], "radius": 1, "intensity": [1, 1, 1]})", "position");
  second("pnull.json", R"({"position": [0, null, 0], "radius": 1, "intensity": [1, 1, 1]})", "position");
  second("pobj.json", R"({"position": {"x": 0, "y": 1}, "radius": 1, "intensity": [1, 1, 1]})", "position");
  second("phuge.json", R"({"position": [0, -1e300, 0], "radius": 1, "intensity": [1, 1, 1]})", "finite");
  second("ineg.json", R"({"position": [0, 0, 0], "radius": 1, "intensity": [1, -1, 1]})", "intensity");
  second("imissing.json", R"({"position": [0, 0, 0], "radius": 1})", "intensity");
  second("notobj.json", R"([0, 0, 0])", "object");
}

TEST(LightVolumes, LoadsAndValidates) {
  TempDir dir;
  const std::string path = dir.write("volumes.json", R"({"radius": 2.5, "radius_jitter": 0.25, "seed": 18446744073709551615,
    "count": 77, "volumes": [{"min": [0, 0, 0], "max": [1, 2, 3], "weight": 2}, {"min": [5, 5, 5], "max": [6, 6, 6]}]})");
  const ml::LightVolumeSet set = ml::loadLightVolumesJson(path);
  ASSERT_EQ(set.volumes.size(), 2u);
  EXPECT_EQ(set.volumes[0].max, glm::vec3(1, 2, 3));
  EXPECT_EQ(set.volumes[0].weight, 2.0f);
  EXPECT_EQ(set.volumes[1].weight, 1.0f);  // default
  EXPECT_EQ(set.defaults.radius, 2.5f);
  EXPECT_EQ(set.defaults.radius_jitter, 0.25f);
  EXPECT_EQ(set.defaults.seed, 18446744073709551615ull);
  EXPECT_EQ(set.defaults.count, 77u);

  auto bad = [&](const std::string& name, const std::string& text, const std::string& also) {
    const std::string p = dir.write(name, text);
    ml::test::expectFileError([&] { (void)ml::loadLightVolumesJson(p); }, p, also);
  };
  bad("empty.json", R"({"volumes": []})", "volumes");
  bad("inverted.json", R"({"volumes": [{"min": [0, 0, 0], "max": [1, 1, 1]}, {"min": [0, 2, 0], "max": [1, 1, 1]}]})",
      "volume 1");
  bad("negweight.json", R"({"volumes": [{"min": [0, 0, 0], "max": [1, 1, 1], "weight": -1}]})", "weight");
  bad("zeroweights.json", R"({"volumes": [{"min": [0, 0, 0], "max": [1, 1, 1], "weight": 0}]})", "weight");
  bad("jitter.json", R"({"radius_jitter": 1.5, "volumes": [{"min": [0, 0, 0], "max": [1, 1, 1]}]})", "radius_jitter");
  bad("seed.json", R"({"seed": -4, "volumes": [{"min": [0, 0, 0], "max": [1, 1, 1]}]})", "seed");
}

const std::string kDefault = std::string(MANYLIGHTS_TEST_DATA_DIR) + "/default/";

// scripts/make_default_scene.py writes lights.json with its own transcription of
// the generator (Python, double arithmetic, its own mt19937_64); the C++
// generator must reproduce that file from light_volumes.json bit for bit.
TEST(LightDefaultSet, MatchesIndependentPythonGenerator) {
  const ml::LightVolumeSet set = ml::loadLightVolumesJson(kDefault + "light_volumes.json");
  EXPECT_GE(set.volumes.size(), 4u);
  ASSERT_GT(set.defaults.count, 0u);
  const auto shipped = ml::loadLightsJson(kDefault + "lights.json");
  ASSERT_EQ(shipped.size(), set.defaults.count);
  const auto generated = ml::generateLights(set.volumes, set.defaults);
  ASSERT_EQ(generated.size(), shipped.size());
  for (std::size_t i = 0; i < shipped.size(); ++i) {
    ASSERT_EQ(pos(generated[i]), pos(shipped[i])) << "light " << i;
    ASSERT_EQ(generated[i].position_radius.w, shipped[i].position_radius.w) << "light " << i;
    ASSERT_EQ(col(generated[i]), col(shipped[i])) << "light " << i;
  }
  for (const auto& l : shipped) {
    bool inside = false;
    for (const auto& v : set.volumes) inside = inside || inBox(pos(l), v);
    EXPECT_TRUE(inside);
  }
}

}  // namespace
