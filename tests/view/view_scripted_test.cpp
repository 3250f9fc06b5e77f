// `manylights view` under Xvfb: a scripted session shows every registered
// technique at one camera (orbited by a fresh random angle, recorded) with a
// regenerated light count, and each screenshot equals `render` of that camera
// and count; view modes equal render's images; path playback and light
// animation equal render's frames; a recorded path replayed through
// `bench --camera` gives the same frames; the window capture holds the panel.
#include <gtest/gtest.h>

#include <filesystem>
#include <random>
#include <vector>

#include "host/techniques/Registry.hpp"
#include "host/util/Heatmap.hpp"
#include "view_support.hpp"

namespace ml {
namespace {

using nlohmann::json;

std::vector<std::string> builtInTechniques() {
  std::vector<std::string> names;
  for (const TechniqueInfo& t : techniques())
    if (t.built_in) names.push_back(t.name);
  return names;
}

// A fresh angle per run, printed so a failure can be replayed.
float freshYaw() {
  const unsigned seed = std::random_device{}();
  std::printf("view test seed %u\n", seed);
  std::mt19937 rng(seed);
  return std::uniform_real_distribution<float>(-40.0f, 40.0f)(rng);
}

TEST(ViewScripted, EveryTechniqueEqualsRenderOfTheSameFrame) {
  if (!test::haveXvfb()) GTEST_SKIP() << "xvfb-run is missing (Debian package xvfb): the viewer cannot be tested";
  const std::string dir = test::tempDir() + "/view_techniques";
  std::filesystem::create_directories(dir);
  // A fresh light count, regenerated before the first technique: every switch keeps it.
  const unsigned lights = 24 + unsigned(std::random_device{}() % 64);
  std::printf("lights %u\n", lights);
  json script = json::array({{{"orbit", {freshYaw(), 0.0}}}, {{"record", "start"}}, {{"lights", lights}}});
  const auto names = builtInTechniques();
  for (const std::string& t : names) {
    script.push_back({{"technique", t}});
    script.push_back({{"wait", 1}});
    script.push_back({{"screenshot", dir + "/view_" + t + ".png"}});
  }
  script.push_back({{"record_save", dir + "/camera.json"}});
  script.push_back({{"screenshot_window", dir + "/window.png"}});
  script.push_back({{"wait", 1}});
  const test::CommandResult v = test::runViewScript(script, "techniques");
  ASSERT_EQ(v.exit_code, 0) << v.out << v.err;
  EXPECT_NE(v.out.find("GLFW window"), std::string::npos) << v.out;
  for (const std::string& t : names) {
    SCOPED_TRACE(t);
    const std::string ref = dir + "/render_" + t + ".png";
    const auto r = test::runManylights("render --technique " + t + " --size 160x96 --lights " + std::to_string(lights) +
                                       " --camera " + dir + "/camera.json --frames 1 --out " + ref);
    ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
    test::expectSameImage(dir + "/view_" + t + ".png", ref);
    // And the switch shows the brute-force image of its pipeline, within the
    // render tests' tolerance between techniques (summation order of lights).
    unsigned w = 0, h = 0;
    const std::string brute = t.find("forward") != std::string::npos ? "forward" : "deferred";
    const auto diff = test::compareImages(readImageRgba(dir + "/view_" + t + ".png", w, h),
                                          readImageRgba(dir + "/view_" + brute + ".png", w, h), 2.0 / 255.0);
    EXPECT_LT(diff.mean_abs, 0.002) << t << " vs " << brute << " max " << diff.max_abs;
    EXPECT_LT(diff.frac_over_tol, 0.005) << t << " vs " << brute << " max " << diff.max_abs;
  }
  // The window capture (panel included) is the window's size and not the bare frame.
  unsigned w = 0, h = 0;
  const auto window = readImageRgba(dir + "/window.png", w, h);
  const auto frame = readImageRgba(dir + "/view_" + names.back() + ".png", w, h);
  EXPECT_EQ(window.size(), frame.size());
  EXPECT_GT(test::compareImages(window, frame, 2.0 / 255.0).frac_over_tol, 0.01) << "no panel in the window capture";
}

// The heat-map, ratio-map and debug-view modes show what `render --heatmap`,
// `render --ratio-map` (less their colour bars) and `render --NAME-view`
// write for the same frame.
TEST(ViewScripted, ViewModesEqualRenderOutputs) {
  if (!test::haveXvfb()) GTEST_SKIP() << "xvfb-run is missing (Debian package xvfb): the viewer cannot be tested";
  const std::string dir = test::tempDir() + "/view_modes";
  std::filesystem::create_directories(dir);
  const std::string heat_technique = builtInTechniques().back();
  json script = json::array({{{"orbit", {freshYaw(), 0.0}}}, {{"record", "start"}},
                             {{"technique", heat_technique}}, {{"view", "heatmap"}}, {{"wait", 1}},
                             {{"screenshot", dir + "/view_heat.png"}}, {{"view", "ratio-map"}},
                             {{"ratio_max", 3.5}}, {{"wait", 1}}, {{"screenshot", dir + "/view_ratio.png"}}});
  std::vector<std::pair<std::string, std::string>> views;  // technique, view
  for (const TechniqueInfo& t : techniques())
    for (const DebugViewSpec& v : t.descriptor->debug_views)
      if (t.built_in) views.emplace_back(t.name, v.name);
  for (const auto& [t, v] : views) {
    script.push_back({{"technique", t}});
    script.push_back({{"view", v}});
    script.push_back({{"wait", 1}});
    script.push_back({{"screenshot", dir + "/view_" + t + "_" + v + ".png"}});
  }
  script.push_back({{"record_save", dir + "/camera.json"}});
  const test::CommandResult run = test::runViewScript(script, "modes");
  ASSERT_EQ(run.exit_code, 0) << run.out << run.err;
  const std::string common = std::string(test::kViewFrame) + " --camera " + dir + "/camera.json --frames 1 ";
  const auto heat = test::runManylights("render --technique " + heat_technique + " " + common + "--heatmap " + dir +
                                        "/render_heat.png --ratio-max 3.5 --ratio-map " + dir + "/render_ratio.png");
  ASSERT_EQ(heat.exit_code, 0) << heat.out << heat.err;
  // render's maps carry their colour bar below the map: compare the map.
  for (const std::string name : {"heat", "ratio"}) {
    SCOPED_TRACE(name);
    unsigned w = 0, h = 0;
    auto with_bar = readImageRgba(dir + "/render_" + name + ".png", w, h);
    with_bar.erase(with_bar.begin(), with_bar.begin() + std::ptrdiff_t(std::size_t(w) * colourBarRows(w) * 4));
    writeImage(dir + "/render_" + name + "_map.png", w, h - colourBarRows(w), 4, with_bar);
    test::expectSameImage(dir + "/view_" + name + ".png", dir + "/render_" + name + "_map.png");
  }
  for (const auto& [t, v] : views) {
    SCOPED_TRACE(t + " " + v);
    const std::string ref = dir + "/render_" + t + "_" + v + ".png";
    const auto r = test::runManylights("render --technique " + t + " " + common + DebugViewSpec{v, ""}.flag() + " " + ref);
    ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
    test::expectSameImage(dir + "/view_" + t + "_" + v + ".png", ref);
  }
}

// The scene's camera path plays one path frame per frame and stays put when
// paused; animated lights take render --animate's steps and stop when
// animation is turned off. Screenshots as EXR (floats), as render writes them.
TEST(ViewScripted, PathPlaybackAndAnimationMatchRender) {
  if (!test::haveXvfb()) GTEST_SKIP() << "xvfb-run is missing (Debian package xvfb): the viewer cannot be tested";
  const std::string dir = test::tempDir() + "/view_play";
  std::filesystem::create_directories(dir);
  const unsigned seed = std::random_device{}();
  std::printf("view test seed %u\n", seed);
  std::mt19937 rng(seed);
  const unsigned start = rng() % 40, steps = 1 + rng() % 4;
  const json script = json::array({{{"technique", "tiled-deferred"}}, {{"camera_frame", start}}, {{"play", true}},
                                   {{"wait", steps}}, {{"play", false}}, {{"screenshot", dir + "/played.exr"}},
                                   {{"wait", 2}}, {{"screenshot", dir + "/paused.exr"}},
                                   {{"animate", {0.3, 0.5}}}, {{"wait", 3}}, {{"screenshot", dir + "/animated.exr"}},
                                   {{"animate", {0.0, 0.5}}}, {{"wait", 2}}, {{"screenshot", dir + "/stopped.exr"}}});
  const test::CommandResult v = test::runViewScript(script, "play");
  ASSERT_EQ(v.exit_code, 0) << v.out << v.err;
  const std::string frame = std::to_string(start + steps);
  const std::string common = "render --technique tiled-deferred " + std::string(test::kViewFrame) + " --frame " + frame;
  const auto still = test::runManylights(common + " --frames 1 --out " + dir + "/render_still.exr");
  ASSERT_EQ(still.exit_code, 0) << still.out << still.err;
  const auto moved = test::runManylights(common + " --warmup 0 --frames 3 --animate 0.3 --animate-speed 0.5 --out " +
                                         dir + "/render_animated.exr");
  ASSERT_EQ(moved.exit_code, 0) << moved.out << moved.err;
  test::expectSameImage(dir + "/played.exr", dir + "/render_still.exr");
  test::expectSameImage(dir + "/paused.exr", dir + "/render_still.exr");
  test::expectSameImage(dir + "/animated.exr", dir + "/render_animated.exr");
  test::expectSameImage(dir + "/stopped.exr", dir + "/render_animated.exr");
  unsigned w = 0, h = 0;
  const auto a = readImageRgba(dir + "/animated.exr", w, h), b = readImageRgba(dir + "/played.exr", w, h);
  // Unmoved lights give the same image exactly; moved ones change from 0.9%
  // (seed 3120093997: a camera frame that sees few of them) to tens of percent of the pixels.
  EXPECT_GT(test::compareImages(a, b, 2.0 / 255.0).frac_over_tol, 0.002) << "the lights did not move";
}

TEST(ViewScripted, RecordedPathReplaysThroughBench) {
  if (!test::haveXvfb()) GTEST_SKIP() << "xvfb-run is missing (Debian package xvfb): the viewer cannot be tested";
  const std::string dir = test::tempDir() + "/view_record";
  std::filesystem::create_directories(dir + "/bench");
  const float yaw = freshYaw();
  json script = json::array({{{"technique", "tiled-deferred"}}, {{"panel", false}}, {{"record", "start"}}});
  const std::vector<json> moves = {{{"orbit", {yaw, 5.0}}}, {{"fly", {0.5, 0.2, 0.1}}}, {{"orbit", {-2 * yaw, -5.0}}}};
  for (std::size_t i = 0; i < moves.size(); ++i) {
    script.push_back(moves[i]);
    script.push_back({{"wait", 1}});
    script.push_back({{"screenshot", dir + "/view_" + std::to_string(i) + ".png"}});
  }
  script.push_back({{"record_save", dir + "/path.json"}});
  const test::CommandResult v = test::runViewScript(script, "record");
  ASSERT_EQ(v.exit_code, 0) << v.out << v.err;
  std::ifstream in(dir + "/path.json");
  const json path = json::parse(in);
  ASSERT_EQ(path.at("frames").size(), moves.size()) << path.dump();

  const auto b = test::runManylights("bench --techniques tiled-deferred " + std::string(test::kViewFrame) +
                                     " --camera " + dir + "/path.json --no-counts --repeat 1 --warmup 0 --progress none"
                                     " --images " + dir + "/bench");
  ASSERT_EQ(b.exit_code, 0) << b.out << b.err;
  for (std::size_t i = 0; i < moves.size(); ++i) {
    SCOPED_TRACE(i);
    std::string replayed;
    for (const auto& e : std::filesystem::directory_iterator(dir + "/bench"))
      if (e.path().filename().string().ends_with("_f" + std::to_string(i) + ".png")) replayed = e.path().string();
    ASSERT_FALSE(replayed.empty()) << "bench wrote no frame " << i;
    test::expectSameImage(dir + "/view_" + std::to_string(i) + ".png", replayed);
  }
}

TEST(ViewScripted, RefusedValueNamesTheAction) {
  if (!test::haveXvfb()) GTEST_SKIP() << "xvfb-run is missing (Debian package xvfb): the viewer cannot be tested";
  const auto r = test::runViewScript(json::array({{{"wait", 1}}, {{"param", {{"tile", "257"}}}}}), "refused");
  EXPECT_EQ(r.exit_code, 2) << r.out << r.err;
  EXPECT_NE(r.err.find("action 1 (param)"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("tile"), std::string::npos) << r.err;
}

TEST(ViewCli, NoDisplayIsOneLineNamingDisplay) {
  for (const char* env : {"-u DISPLAY", "DISPLAY="}) {
    SCOPED_TRACE(env);
    const auto r = test::runManylights("view --size 64x64", env);
    EXPECT_EQ(r.exit_code, 2);
    EXPECT_NE(r.err.find("DISPLAY"), std::string::npos) << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    EXPECT_EQ(r.out, "");
  }
}

TEST(ViewCli, BadScriptIsRefusedBeforeAWindowOpens) {
  const std::string dir = test::tempDir() + "/view_bad";
  std::filesystem::create_directories(dir);
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"[{\"jump\": 1}]", "unknown action 'jump'"},
      {"[{\"wait\": -1}]", "wait"},
      {"[{\"orbit\": [1]}]", "orbit"},
      {"[{\"technique\": \"a\", \"wait\": 1}]", "one key"},
      {"{\"actions\": 3}", "array"},
      {"[{", "invalid JSON"}};
  for (std::size_t i = 0; i < cases.size(); ++i) {
    SCOPED_TRACE(cases[i].first);
    const std::string file = dir + "/s" + std::to_string(i) + ".json";
    std::ofstream(file) << cases[i].first;
    const auto r = test::runManylights("view --script " + file, "-u DISPLAY");
    EXPECT_EQ(r.exit_code, 2);
    EXPECT_NE(r.err.find(file), std::string::npos) << r.err;
    EXPECT_NE(r.err.find(cases[i].second), std::string::npos) << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  }
  const auto missing = test::runManylights("view --script " + dir + "/none.json", "-u DISPLAY");
  EXPECT_EQ(missing.exit_code, 2);
  EXPECT_NE(missing.err.find("none.json"), std::string::npos) << missing.err;
}

}  // namespace
}  // namespace ml
