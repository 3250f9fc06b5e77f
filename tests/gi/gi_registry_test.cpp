// A GI pass is a descriptor plus one registration: the test-only constant
// ambient pass (tests/extensions/ambient_gi/TestOnlyGiPass.cpp), which no front end names,
//  - shows in `render --help` (its --ambient flag, its --gi name) and in
//    `bench --help`'s keys, and a bad value is refused up front naming --ambient;
//  - adds exactly albedo x its colour to the frame (fresh random colour per
//    run; tolerance: float rounding of one addition, 1e-6 relative);
//  - renders through `render` (its files and stats fields) and `bench --gi`
//    (one record per swept value), run in this binary (in a child process);
//  - is driven by the viewer's GI state as VCT is (the panel's widgets and
//    script keys come from the same descriptor).
#include "ml_test_paths.h"  // MANYLIGHTS_TEST_DATA_DIR
#include <gtest/gtest.h>

#include <epoxy/gl.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <random>
#include <set>
#include <cstdlib>
#include <iterator>
#include <string>

#include "gl/FrameRenderer.hpp"
#include "host/gi/Registry.hpp"
#include "host/techniques/Registry.hpp"
#include "host/util/Error.hpp"
#include "host/view/ViewerGi.hpp"
#include "support/BruteReference.hpp"
#include "support/InProcessCli.hpp"
#include "support/RunCommand.hpp"
#include "support/TempDir.hpp"
#include "support/TestDevice.hpp"
#include "support/TestGl.hpp"
#include "extensions/ambient_gi/TestOnlyGiPass.hpp"

namespace ml {
namespace {

using test::runCliInProcess;

bool has(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

std::vector<std::string> cornellArgs(const std::string& command) {
  const std::string dir = std::string(MANYLIGHTS_TEST_DATA_DIR) + "/cornell/";
  return {command, "--scene", dir + "cornell.gltf", "--lights", dir + "lights.json", "--camera", dir + "camera.json",
          "--warmup", "0"};
}

TEST(GiRegistry, TestOnlyPassShowsInHelpAndIsCheckedUpFront) {
  const auto render = runCliInProcess({"render", "--help"});
  EXPECT_EQ(render.exit_code, 0);
  EXPECT_TRUE(has(render.out, test::kAmbientGiName)) << render.out;
  EXPECT_TRUE(has(render.out, "--ambient") && has(render.out, "default 0.25:0.5:0.75")) << render.out;
  const auto bench = runCliInProcess({"bench", "--help"});
  EXPECT_TRUE(has(bench.out, std::string("with --gi ") + test::kAmbientGiName + " also its settings")) << bench.out;
  for (const std::vector<std::string>& bad :
       {std::vector<std::string>{"render", "--size", "16x16", "--gi", test::kAmbientGiName, "--ambient", "1:x:0"},
        {"render", "--size", "16x16", "--gi", test::kAmbientGiName, "--gi-param", "ambient=-1:0:0"},
        {"bench", "--size", "16x16", "--gi", test::kAmbientGiName, "--param", "ambient=1:1:1,1:1"}}) {
    const auto r = runCliInProcess(bad);
    EXPECT_EQ(r.exit_code, 2) << r.err;
    EXPECT_EQ(r.out, "");  // nothing opened or rendered
    EXPECT_TRUE(has(r.err, "--ambient") && has(r.err, "R:G:B")) << r.err;
  }
  const auto ref = runCliInProcess({"render", "--size", "16x16", "--gi", test::kAmbientGiName, "--gi-reference"});
  EXPECT_EQ(ref.exit_code, 2) << "no reference transport described: --gi-reference must be refused";
}

std::vector<float> texture(GLuint tex, unsigned w, unsigned h) {
  std::vector<float> px(std::size_t(w) * h * 4);
  glGetTextureImage(tex, 0, GL_RGBA, GL_FLOAT, GLsizei(px.size() * sizeof(float)), px.data());
  return px;
}

TEST(GiRegistry, AmbientPassAddsAlbedoTimesItsColour) {
  test::glContext();
  const std::uint64_t seed = test::freshSeed();
  SCOPED_TRACE("seed=" + std::to_string(seed));
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<float> u(0.05f, 2.0f);
  const glm::vec3 c(u(rng), u(rng), u(rng));
  const std::string text = std::to_string(c.x) + ":" + std::to_string(c.y) + ":" + std::to_string(c.z);
  glm::vec3 parsed;
  ASSERT_TRUE(test::parseAmbient(text, parsed));
  const SceneInputs& in = test::referenceScene();
  constexpr unsigned kW = 64, kH = 36;
  FrameRenderer r(test::runtime(), in.scene, kW, kH);
  r.setLights(in.lights);
  const Camera& cam = in.cameras.frames.front();
  const auto assigner = makeAssigner("deferred", test::runtime());
  r.render(cam, *assigner, {Pipeline::Deferred, false});
  const std::vector<float> direct = r.targets().readColor();
  const GiDescriptor& d = findGi(test::kAmbientGiName);
  const auto pass = makeGiPass(d, test::runtime(), giParams(d, {{"ambient", text}}), in.scene);
  r.render(cam, *assigner, {Pipeline::Deferred, false, true, pass.get()});
  const std::vector<float> lit = r.targets().readColor(), albedo = texture(r.targets().albedoTexture(), kW, kH);
  const std::vector<float> indirect = pass->indirectRgba();
  ASSERT_EQ(indirect.size(), albedo.size());
  std::size_t covered = 0, worst = 0;
  double worst_err = 0;
  for (std::size_t p = 0; p < albedo.size() / 4; ++p) {
    covered += indirect[4 * p + 3] == 1.0f;
    for (int k = 0; k < 3; ++k) {
      const float want = indirect[4 * p + 3] == 1.0f ? albedo[4 * p + k] * parsed[k] : 0.0f;
      EXPECT_EQ(indirect[4 * p + k], want) << "pixel " << p;
      const double err = std::abs(double(lit[4 * p + k]) - direct[4 * p + k] - want) /
                         (1e-6 * std::max({1.0, std::abs(double(lit[4 * p + k]))}));
      if (err > worst_err) worst_err = err, worst = p;
    }
  }
  EXPECT_GT(covered, albedo.size() / 8) << "the scene should cover much of the frame";
  EXPECT_LE(worst_err, 1.0) << "frame - direct differs from albedo x colour beyond 1e-6 relative at pixel " << worst;
}

// The child half of RenderAndBenchRunTheTestPass, run by it in a process of
// its own (never alone: disabled): `render` and `bench` in-process close the
// EGL display this binary's GL tests share (EglContext terminates it), so
// they must not run inside the test process. Writes into $ML_GI_CHILD_DIR.
TEST(GiRegistryChild, DISABLED_RenderAndBenchInThisProcess) {
  const char* dir = std::getenv("ML_GI_CHILD_DIR");
  ASSERT_NE(dir, nullptr);
  const std::string d = dir;
  std::vector<std::string> render = cornellArgs("render");
  render.insert(render.end(), {"--size", "48x32", "--frames", "1", "--gi", test::kAmbientGiName, "--ambient",
                               "0.5:0.25:1", "--out", d + "/a.png", "--stats-json", d + "/a.json"});
  const auto r = runCliInProcess(render);
  std::ofstream(d + "/render.out") << r.exit_code << "\n" << r.out << r.err;
  std::vector<std::string> bench = cornellArgs("bench");
  bench.insert(bench.end(), {"--techniques", "deferred", "--size", "48x32", "--frames", "0", "--progress", "none",
                             "--gi", test::kAmbientGiName, "--param", "ambient=0:0:0,1:1:1", "--no-counts", "--json",
                             d + "/b.json"});
  const auto b = runCliInProcess(bench);
  std::ofstream(d + "/bench.out") << b.exit_code << "\n" << b.out << b.err;
}

std::string fileText(const std::string& path) {
  std::ifstream in(path);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

TEST(GiRegistry, RenderAndBenchRunTheTestPass) {
  test::TempDir tmp;
  const std::string self = std::filesystem::read_symlink("/proc/self/exe").string();
  // The shard variables are unset for the child: under sharding its one test
  // would otherwise fall to another shard and the child would run nothing.
  const auto child = test::runShell("env -u GTEST_TOTAL_SHARDS -u GTEST_SHARD_INDEX ML_GI_CHILD_DIR=" +
                                    tmp.file("") + " " + self +
                                    " --gtest_filter=GiRegistryChild.DISABLED_RenderAndBenchInThisProcess"
                                    " --gtest_also_run_disabled_tests");
  ASSERT_EQ(child.exit_code, 0) << child.out << child.err;
  ASSERT_TRUE(has(child.out, "[  PASSED  ] 1 test")) << "the child ran no test:\n" << child.out;
  const std::string render = fileText(tmp.file("render.out")), bench = fileText(tmp.file("bench.out"));
  ASSERT_EQ(render.rfind("0\n", 0), 0u) << render;
  EXPECT_TRUE(has(render, "gi test-ambient: ")) << render;
  for (const char* f : {"a_gi_test-ambient.exr", "a_gi_test-ambient.png"})
    EXPECT_TRUE(std::filesystem::exists(tmp.file(f))) << f;
  const nlohmann::json j = nlohmann::json::parse(std::ifstream(tmp.file("a.json")));
  EXPECT_EQ(j.at("gi"), test::kAmbientGiName);
  EXPECT_EQ(j.at("gi_ambient"), nlohmann::json({0.5, 0.25, 1.0}));

  ASSERT_EQ(bench.rfind("0\n", 0), 0u) << bench;
  const auto recs = nlohmann::json::parse(std::ifstream(tmp.file("b.json"))).at("records");
  ASSERT_EQ(recs.size(), 2u);
  std::set<std::string> seen;
  for (const auto& rec : recs) {
    EXPECT_EQ(rec.at("gi"), test::kAmbientGiName);
    seen.insert(rec.at("gi_settings").at("ambient").get<std::string>());
    EXPECT_EQ(rec.at("gi_updates"), 1);
  }
  EXPECT_EQ(seen, (std::set<std::string>{"0:0:0", "1:1:1"}));
}

TEST(GiRegistry, TheViewerDrivesTheTestPassFromItsDescriptor) {
  test::glContext();
  ViewerGi gi(test::runtime(), test::referenceScene().scene);
  gi.setMode(test::kAmbientGiName);
  ASSERT_TRUE(gi.on());
  EXPECT_EQ(gi.descriptor().name, test::kAmbientGiName);
  EXPECT_EQ(gi.params().text("ambient"), "0.25:0.5:0.75");
  const GiPass* before = gi.pass();
  try {
    gi.setParam("ambient", "1:1");
    ADD_FAILURE() << "a bad colour was accepted";
  } catch (const UserError& e) {
    EXPECT_TRUE(has(e.what(), "--ambient")) << e.what();
  }
  EXPECT_EQ(gi.pass(), before) << "a refused value rebuilt the pass";
  gi.setParam("ambient", "1:2:3");
  EXPECT_EQ(gi.params().text("ambient"), "1:2:3");
  EXPECT_THROW(gi.viewImage(Camera{}, 8, 8), UserError) << "the test pass has no view of its own";
  gi.setMode("vct");  // and back: each pass keeps what was set for it
  gi.setMode(test::kAmbientGiName);
  EXPECT_EQ(gi.params().text("ambient"), "1:2:3");
}

}  // namespace
}  // namespace ml
