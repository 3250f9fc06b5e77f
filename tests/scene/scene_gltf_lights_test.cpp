// glTF point lights (KHR_lights_punctual, host/scene/GltfLights.hpp): a file
// written here with nested node transforms, lights with and without range
// (every expected position, colour and radius computed by hand in the
// comments), malformed light entries (one line naming the file, exit 2 from
// the CLI), the write / read round trip on fresh random sets, the Cornell
// box's lights, and render/bench using, reporting and writing them.
#include "ml_test_paths.h"  // MANYLIGHTS_TEST_DATA_DIR, MANYLIGHTS_BINARY (generated)
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <glm/glm.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <fstream>
#include <random>
#include <string>
#include <vector>

#include "host/scene/GltfLights.hpp"
#include "host/scene/LightSet.hpp"
#include "host/scene/Scene.hpp"
#include "host/util/ThesisSeed.hpp"
#include "support/FileErrors.hpp"
#include "support/RunCommand.hpp"
#include "support/TempDir.hpp"
#include "support/TestDevice.hpp"  // freshSeed

namespace ml {
namespace {

using nlohmann::json;
using test::TempDir;

const std::string kCornell = std::string(MANYLIGHTS_TEST_DATA_DIR) + "/cornell/";

// One triangle (so that the mesh loader takes the file too), base64 as in
// fuzz/corpus/gltf/triangle.gltf.
json triangleParts() {
  return json::parse(R"({
    "meshes": [{"primitives": [{"attributes": {"POSITION": 0}}]}],
    "buffers": [{"byteLength": 36, "uri": "data:application/octet-stream;base64,AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAAAAAAAAAAgD8AAAAA"}],
    "bufferViews": [{"buffer": 0, "byteLength": 36}],
    "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
                   "min": [0, 0, 0], "max": [1, 1, 0]}]})");
}

json lightRef(int light) { return {{"KHR_lights_punctual", {{"light", light}}}}; }

// The scene of LightsFollowNestedTransforms:
//   A (root): translation (1, 2, 3), scale 2; children B, G
//     B: rotation 90 degrees about +y, translation (1, 0, 0); child C
//       C: translation (0, 0, 1), light 0
//     G: translation (0, 1, 0), light 1
//   D (root): matrix translating by (-1, 0.5, 0), light 1 again
//   E (root): light 2 (spot); F (root): light 3 (directional); M (root): the triangle
// Table: 0 point, range 5, colour (1, 0.5, 0.25), intensity 4; 1 point, no
// range, no colour, intensity 0.25; 2 spot; 3 directional; 4 point, no node.
json nestedScene() {
  json doc = triangleParts();
  doc["asset"] = {{"version", "2.0"}};
  doc["extensionsUsed"] = {"KHR_lights_punctual"};
  const double h = std::sqrt(0.5);
  doc["nodes"] = json::array({
      {{"name", "A"}, {"translation", {1, 2, 3}}, {"scale", {2, 2, 2}}, {"children", {1, 3}}},
      {{"name", "B"}, {"rotation", {0, h, 0, h}}, {"translation", {1, 0, 0}}, {"children", {2}}},
      {{"name", "C"}, {"translation", {0, 0, 1}}, {"extensions", lightRef(0)}},
      {{"name", "G"}, {"translation", {0, 1, 0}}, {"extensions", lightRef(1)}},
      {{"name", "D"},
       {"matrix", {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, -1, 0.5, 0, 1}},
       {"extensions", lightRef(1)}},
      {{"name", "E"}, {"extensions", lightRef(2)}},
      {{"name", "F"}, {"extensions", lightRef(3)}},
      {{"name", "M"}, {"mesh", 0}},
  });
  doc["scenes"] = json::array({{{"nodes", {0, 4, 5, 6, 7}}}});
  doc["scene"] = 0;
  doc["extensions"]["KHR_lights_punctual"]["lights"] = json::array({
      {{"type", "point"}, {"range", 5}, {"color", {1, 0.5, 0.25}}, {"intensity", 4}},
      {{"type", "point"}, {"intensity", 0.25}},
      {{"type", "spot"}, {"spot", {{"outerConeAngle", 0.5}}}},
      {{"type", "directional"}},
      {{"type", "point"}},
  });
  return doc;
}

void expectLight(const gpu::PointLight& l, glm::vec3 p, float r, glm::vec3 c) {
  EXPECT_NEAR(l.position_radius.x, p.x, 1e-5f);
  EXPECT_NEAR(l.position_radius.y, p.y, 1e-5f);
  EXPECT_NEAR(l.position_radius.z, p.z, 1e-5f);
  EXPECT_FLOAT_EQ(l.position_radius.w, r);
  EXPECT_FLOAT_EQ(l.color.x, c.x);
  EXPECT_FLOAT_EQ(l.color.y, c.y);
  EXPECT_FLOAT_EQ(l.color.z, c.z);
}

TEST(SceneGltfLights, LightsFollowNestedTransforms) {
  TempDir dir;
  const std::string path = dir.write("nested.gltf", nestedScene().dump());
  const GltfLightTable t = loadGltfLights(path);
  ASSERT_EQ(t.lights.size(), 3u);
  // C: (0,0,1) turned 90 degrees about +y is (1,0,0), + B's (1,0,0) = (2,0,0);
  // A scales by 2 and moves by (1,2,3): (5,2,3). Range 5 (not scaled);
  // colour (1, 0.5, 0.25) x 4.
  expectLight(t.lights[0], {5, 2, 3}, 5.0f, {4, 2, 1});
  // G: (0,1,0) x 2 + (1,2,3) = (1,4,3). No range: sqrt(0.25 / (1/256)) = 8;
  // no colour: white x 0.25.
  expectLight(t.lights[1], {1, 4, 3}, 8.0f, {0.25f, 0.25f, 0.25f});
  // D: its matrix's translation column.
  expectLight(t.lights[2], {-1, 0.5f, 0}, 8.0f, {0.25f, 0.25f, 0.25f});
  EXPECT_EQ(t.table_size, 5u);
  EXPECT_EQ(t.spot, 1u);
  EXPECT_EQ(t.directional, 1u);
  EXPECT_EQ(t.unplaced, 1u);
  EXPECT_EQ(t.dark, 0u);
  const std::string note = t.skippedNote();
  for (const char* part : {"1 spot light", "1 directional light", "1 light that no node", "3 point lights used"})
    EXPECT_NE(note.find(part), std::string::npos) << note;

  // A threshold of 0.01: sqrt(0.25 / 0.01) = 5; the ranged light keeps 5.
  const GltfLightTable t2 = loadGltfLights(path, 0.01f);
  ASSERT_EQ(t2.lights.size(), 3u);
  EXPECT_FLOAT_EQ(t2.lights[0].position_radius.w, 5.0f);
  EXPECT_FLOAT_EQ(t2.lights[1].position_radius.w, 5.0f);

  // The scene loader reads the same lights.
  const Scene s = loadGltfScene(path);
  ASSERT_EQ(s.lights.size(), 3u);
  EXPECT_EQ(std::memcmp(s.lights.data(), t.lights.data(), 3 * sizeof(gpu::PointLight)), 0);
  EXPECT_EQ(s.triangleCount(), 1u);
}

TEST(SceneGltfLights, ThresholdRadiusInvertsTheInverseSquareFalloff) {
  const std::uint64_t seed = test::freshSeed();  // recorded; MANYLIGHTS_TEST_SEED replays it
  SCOPED_TRACE("seed " + std::to_string(seed));
  std::mt19937_64 gen(seed);
  std::uniform_real_distribution<float> u(0.01f, 50.0f);
  for (int i = 0; i < 100; ++i) {
    const glm::vec3 c(u(gen), u(gen), u(gen));
    const float t = u(gen) / 1000.0f;
    const float r = thresholdRadius(c, t);
    // At r the brightest channel's I / d^2 is the threshold.
    const float brightest = std::max({c.r, c.g, c.b});
    EXPECT_NEAR(brightest / (r * r), t, t * 1e-5f);
  }
  EXPECT_EQ(thresholdRadius(glm::vec3(0.0f), 0.01f), 0.0f);
}

TEST(SceneGltfLights, FileWithoutTheExtensionHasNoLights) {
  TempDir dir;
  json doc = triangleParts();
  doc["asset"] = {{"version", "2.0"}};
  doc["nodes"] = json::array({{{"mesh", 0}}});
  const std::string path = dir.write("plain.gltf", doc.dump());
  EXPECT_TRUE(loadGltfScene(path).lights.empty());
  EXPECT_TRUE(loadGltfLights(path).lights.empty());
  EXPECT_EQ(loadGltfLights(path).table_size, 0u);
}

TEST(SceneGltfLights, RangeLessDarkLightIsSkippedAndCounted) {
  TempDir dir;
  json doc = nestedScene();
  doc["extensions"]["KHR_lights_punctual"]["lights"][1]["intensity"] = 0;
  const GltfLightTable t = loadGltfLights(dir.write("dark.gltf", doc.dump()));
  EXPECT_EQ(t.lights.size(), 1u);
  EXPECT_EQ(t.dark, 2u);  // light 1, placed twice
  EXPECT_NE(t.skippedNote().find("2 point lights without range and with zero intensity"), std::string::npos);
}

// Each malformation of `nestedScene`, with a word the message must contain.
struct Malformed {
  const char* name;
  void (*edit)(json&);
  const char* mentions;
};

json& table(json& doc) { return doc["extensions"]["KHR_lights_punctual"]["lights"]; }

const Malformed kMalformed[] = {
    {"negative range", [](json& d) { table(d)[0]["range"] = -1; }, "range"},
    {"zero range", [](json& d) { table(d)[0]["range"] = 0; }, "range"},
    {"range as text", [](json& d) { table(d)[0]["range"] = "far"; }, "range"},
    {"unknown type", [](json& d) { table(d)[4]["type"] = "area"; }, "unknown type"},
    {"colour of two", [](json& d) { table(d)[0]["color"] = {1, 1}; }, "color"},
    {"colour as text", [](json& d) { table(d)[0]["color"] = "red"; }, "color"},
    {"colour with text", [](json& d) { table(d)[0]["color"] = {1, "x", 1}; }, "color"},
    {"colour empty", [](json& d) { table(d)[0]["color"] = json::array(); }, "color"},
    {"negative colour", [](json& d) { table(d)[0]["color"] = {1, -0.5, 1}; }, "color"},
    {"negative intensity", [](json& d) { table(d)[1]["intensity"] = -2; }, "intensity"},
    {"intensity as text", [](json& d) { table(d)[1]["intensity"] = "bright"; }, "intensity"},
    {"light that does not exist", [](json& d) { d["nodes"][2]["extensions"] = lightRef(7); }, "does not exist"},
    {"negative light index", [](json& d) { d["nodes"][2]["extensions"] = lightRef(-1); }, "does not exist"},
    {"light index as text", [](json& d) { d["nodes"][2]["extensions"]["KHR_lights_punctual"]["light"] = "0"; },
     "light"},
    {"table not an array", [](json& d) { d["extensions"]["KHR_lights_punctual"]["lights"] = 5; }, "lights"},
    {"entry not an object", [](json& d) { table(d)[4] = 5; }, ""},
    {"missing type", [](json& d) { table(d)[4].erase("type"); }, ""},
    {"overflowing colour x intensity", [](json& d) { table(d)[0]["intensity"] = 1e300; }, "intensity"},
};

TEST(SceneGltfLights, MalformedEntriesAreOneLineNamingTheFile) {
  TempDir dir;
  for (const Malformed& m : kMalformed) {
    SCOPED_TRACE(m.name);
    json doc = nestedScene();
    m.edit(doc);
    const std::string path = dir.write("bad.gltf", doc.dump());
    test::expectFileError([&] { (void)loadGltfLights(path); }, path, m.mentions);
    test::expectFileError([&] { (void)loadGltfScene(path); }, path, m.mentions);
  }
}

TEST(SceneGltfLights, AbsentColourIsWhiteAsGltfSays) {
  TempDir dir;
  json doc = nestedScene();
  table(doc)[0].erase("color");
  const GltfLightTable t = loadGltfLights(dir.write("white.gltf", doc.dump()));
  ASSERT_FALSE(t.lights.empty());
  expectLight(t.lights[0], {5, 2, 3}, 5.0f, {4, 4, 4});
}

// Fresh random sets of the sizes the project tests with, colours inside and
// beyond [0, 1] and magnitudes far apart: written and read back bit for bit.
std::vector<gpu::PointLight> randomLights(std::mt19937_64& gen, std::size_t n) {
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  std::uniform_int_distribution<int> e(-12, 12);
  std::vector<gpu::PointLight> out;
  for (std::size_t i = 0; i < n; ++i) {
    const float scale = std::ldexp(1.0f, e(gen));
    const glm::vec3 p(u(gen) * scale, u(gen) * 1000.0f, u(gen) * 1e-3f);
    glm::vec3 c(std::abs(u(gen)), std::abs(u(gen)), std::abs(u(gen)));
    if (i % 3 == 1) c *= std::ldexp(1.0f, e(gen));  // brighter than 1, or dimmer
    if (i % 7 == 3) c = glm::vec3(0.0f);             // dark, with its range
    out.push_back(makeLight(p, std::abs(u(gen)) * scale + 1e-6f, c));
  }
  if (n > 2) out[2] = out[1];  // duplicates stay two lights
  return out;
}

TEST(SceneGltfLights, WrittenSetsReadBackIdentical) {
  const std::uint64_t seed = test::freshSeed();
  SCOPED_TRACE("seed " + std::to_string(seed));
  std::mt19937_64 gen(seed);
  TempDir dir;
  for (std::size_t n : {1u, 2u, 7u, 31u, 33u, 255u, 257u}) {
    for (bool binary : {false, true}) {
      SCOPED_TRACE(std::to_string(n) + (binary ? " .glb" : " .gltf"));
      const std::vector<gpu::PointLight> lights = randomLights(gen, n);
      const std::string path = dir.file(binary ? "set.glb" : "set.gltf");
      std::ofstream(path, std::ios::binary) << gltfLightsDocument(lights, binary);
      const GltfLightTable back = loadGltfLights(path);
      ASSERT_EQ(back.lights.size(), n);
      for (std::size_t i = 0; i < n; ++i)
        EXPECT_EQ(std::memcmp(&back.lights[i], &lights[i], sizeof(gpu::PointLight)), 0)
            << "light " << i << ": colour " << lights[i].color.x << " " << lights[i].color.y << " "
            << lights[i].color.z << " read back as " << back.lights[i].color.x << " " << back.lights[i].color.y
            << " " << back.lights[i].color.z;
      EXPECT_EQ(back.skippedNote(), "");
    }
  }
}

TEST(SceneGltfLights, WrittenFileIsPlainKhrLightsPunctual) {
  const std::vector<gpu::PointLight> lights = {makeLight({1, 2, 3}, 2.5f, {0.8f, 0.8f, 0.9f}),
                                               makeLight({0, 1.8f, 0}, 3.5f, {2, 1.9f, 1.7f})};
  const json doc = json::parse(gltfLightsDocument(lights, false));
  EXPECT_EQ(doc["asset"]["version"], "2.0");
  EXPECT_NE(std::find(doc["extensionsUsed"].begin(), doc["extensionsUsed"].end(), "KHR_lights_punctual"),
            doc["extensionsUsed"].end());
  const json& table = doc["extensions"]["KHR_lights_punctual"]["lights"];
  ASSERT_EQ(table.size(), 2u);
  ASSERT_EQ(doc["nodes"].size(), 2u);
  EXPECT_EQ(doc["nodes"][0]["translation"], json({1, 2, 3}));
  EXPECT_EQ(doc["nodes"][1]["extensions"]["KHR_lights_punctual"]["light"], 1);
  EXPECT_EQ(table[0]["type"], "point");
  EXPECT_EQ(table[0]["range"], 2.5);
  EXPECT_EQ(table[0]["intensity"], 1.0);  // within [0, 1]: the colour as it is
  EXPECT_EQ(table[0]["color"][2], 0.9);
  EXPECT_EQ(table[1]["intensity"], 2.0);  // brighter: divided by its largest component
  EXPECT_EQ(table[1]["color"][0], 1.0);
  EXPECT_EQ(doc["scenes"][doc["scene"].get<int>()]["nodes"], json({0, 1}));
}

// The Cornell glTF carries the lights of its lights.json, in the same order,
// bit for bit, so that renders from either are the same.
TEST(SceneGltfLights, CornellBoxCarriesItsLights) {
  const Scene s = loadGltfScene(kCornell + "cornell.gltf");
  const std::vector<gpu::PointLight> json_lights = loadLightsJson(kCornell + "lights.json");
  ASSERT_EQ(s.lights.size(), json_lights.size());
  ASSERT_EQ(s.lights.size(), 4u);
  for (std::size_t i = 0; i < s.lights.size(); ++i)
    EXPECT_EQ(std::memcmp(&s.lights[i], &json_lights[i], sizeof(gpu::PointLight)), 0) << "light " << i;
}

// --- The command line ----------------------------------------------------

void expectRefused(const test::CommandResult& r, const std::string& mention) {
  EXPECT_EQ(r.exit_code, 2) << "stdout: " << r.out << "\nstderr: " << r.err;
  EXPECT_EQ(test::lines(r.err), 1) << r.err;
  EXPECT_NE(r.err.find(mention), std::string::npos) << "expected '" << mention << "' in: " << r.err;
  EXPECT_EQ(r.out, "") << "expected nothing before the error";
}

TEST(GltfLightsCli, MalformedLightsExitTwoWithOneLineNamingTheFile) {
  TempDir dir;
  for (const Malformed& m : kMalformed) {
    const std::string name(m.name);
    if (name != "negative range" && name != "unknown type" && name != "colour of two" &&
        name != "light that does not exist")
      continue;
    SCOPED_TRACE(m.name);
    json doc = nestedScene();
    m.edit(doc);
    const std::string path = dir.write("bad.gltf", doc.dump());
    expectRefused(test::runManylights("render --size 16x16 --lights " + path), path);
    expectRefused(test::runManylights("render --size 16x16 --scene " + path), path);
    expectRefused(test::runManylights("bench --techniques deferred --size 16x16 --frames 0 --lights " + path), path);
  }
}

TEST(GltfLightsCli, WriteLightsIsCheckedBeforeAnythingLoads) {
  TempDir dir;
  expectRefused(test::runManylights("render --size 16x16 --write-lights " + dir.file("l.json")), "--write-lights");
  expectRefused(test::runManylights("bench --techniques deferred --size 16x16 --frames 0 --lights 8,16 "
                                    "--write-lights " + dir.file("l.gltf")),
                "--write-lights");
  expectRefused(test::runManylights("render --size 16x16 --light-threshold 0"), "--light-threshold");
}

std::vector<gpu::PointLight> readBack(const std::string& path) { return loadGltfLights(path).lights; }

void expectSameLights(const std::vector<gpu::PointLight>& a, const std::vector<gpu::PointLight>& b) {
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size(); ++i)
    EXPECT_EQ(std::memcmp(&a[i], &b[i], sizeof(gpu::PointLight)), 0) << "light " << i;
}

// render --scene cornell.gltf uses the file's lights without --lights, says so
// in the stats JSON, and --write-lights writes the set in use (the scene's,
// generated or a glTF's) so that it reads back the same.
TEST(GltfLightsCli, RenderUsesReportsAndWritesTheSetInUse) {
  TempDir dir;
  const std::string scene = "render --size 32x24 --frames 1 --warmup 0 --scene " + kCornell + "cornell.gltf --camera " +
                            kCornell + "camera.json --stats-json " + dir.file("s.json");
  const std::vector<gpu::PointLight> cornell = loadLightsJson(kCornell + "lights.json");

  auto r = test::runManylights(scene + " --write-lights " + dir.file("own.gltf"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  json stats = test::readJson(dir.file("s.json"));
  EXPECT_EQ(stats["lights"], 4);
  EXPECT_EQ(stats["lights_source"], "gltf");
  EXPECT_NE(stats["lights_file"].get<std::string>().find("cornell.gltf"), std::string::npos) << stats["lights_file"];
  expectSameLights(readBack(dir.file("own.gltf")), cornell);

  r = test::runManylights(scene + " --lights 37 --write-lights " + dir.file("gen.glb"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  stats = test::readJson(dir.file("s.json"));
  EXPECT_EQ(stats["lights"], 37);
  EXPECT_EQ(stats["lights_source"], "generated");
  EXPECT_TRUE(stats["lights_file"].is_null());
  const Aabb b = loadGltfScene(kCornell + "cornell.gltf").bounds;
  expectSameLights(readBack(dir.file("gen.glb")), generateLightsIn("", b.min, b.max, 37, kThesisSeed, 0.0f));

  r = test::runManylights(scene + " --lights " + dir.file("gen.glb"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  stats = test::readJson(dir.file("s.json"));
  EXPECT_EQ(stats["lights"], 37);
  EXPECT_EQ(stats["lights_source"], "gltf");
}

TEST(GltfLightsCli, BenchUsesReportsAndWritesTheScenesLights) {
  TempDir dir;
  const auto r = test::runManylights("bench --techniques deferred --size 16x16 --frames 0 --progress none --scene " +
                                     kCornell + "cornell.gltf --camera " + kCornell + "camera.json --json " +
                                     dir.file("b.json") + " --write-lights " + dir.file("w.gltf"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const json meta = test::readJson(dir.file("b.json"))["meta"];
  ASSERT_EQ(meta["light_sets"].size(), 1u);
  EXPECT_EQ(meta["light_sets"][0]["source"], "gltf");
  EXPECT_EQ(meta["light_sets"][0]["count"], 4);
  expectSameLights(readBack(dir.file("w.gltf")), loadLightsJson(kCornell + "lights.json"));
}

}  // namespace
}  // namespace ml
