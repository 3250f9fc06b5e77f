// The technique registry as the commands see it: a technique registered by the
// test binary (extensions/test_technique/TestOnlyTechnique.cpp) shows in `techniques`, `render
// --help` and `bench --help` and renders with its own parameter; every
// parameter of the registry refuses out-of-range values on both command-line
// paths before anything starts; shared keys agree; ranges are what the
// techniques accept.
#include <gtest/gtest.h>

#include <algorithm>

#include "gl/FrameRenderer.hpp"
#include "host/clustered/ClusterGeometry.hpp"
#include "host/techniques/Registry.hpp"
#include "host/tiled/TileLightCuller.hpp"
#include "host/util/Error.hpp"
#include "support/BruteReference.hpp"
#include "support/InProcessCli.hpp"
#include "support/RunCommand.hpp"
#include "support/TestDevice.hpp"
#include "support/TestGl.hpp"

namespace ml {
namespace {

using test::lines;
using test::runCliInProcess;

bool has(const std::string& text, const std::string& what) { return text.find(what) != std::string::npos; }

TEST(TechniqueRegistry, TestOnlyTechniqueIsListedWithItsParameter) {
  const auto list = runCliInProcess({"techniques"});
  EXPECT_EQ(list.exit_code, 0) << list.err;
  EXPECT_TRUE(has(list.out, "test-brute-forward") && has(list.out, "test-brute-deferred")) << list.out;
  EXPECT_FALSE(findTechnique("test-brute-forward").built_in);
  const auto render = runCliInProcess({"render", "--help"});
  EXPECT_EQ(render.exit_code, 0);
  EXPECT_TRUE(has(render.out, "test-brute-deferred")) << render.out;
  EXPECT_TRUE(has(render.out, "--test-knob") && has(render.out, "1..8")) << render.out;
  const auto bench = runCliInProcess({"bench", "--help"});
  EXPECT_EQ(bench.exit_code, 0);
  EXPECT_TRUE(has(bench.out, "test-brute-deferred")) << bench.out;
  EXPECT_TRUE(has(bench.out, "test_knob (1..8; default 2)") && has(bench.out, "--test-knob")) << bench.out;
}

TEST(TechniqueRegistry, TestOnlyTechniqueRendersWithItsParameter) {
  test::glContext();
  const SceneInputs& in = test::referenceScene();
  FrameRenderer r(test::runtime(), in.scene, 64, 36);
  r.setLights(in.lights);
  const Camera& cam = in.cameras.frames.front();
  const TechniqueInfo& t = findTechnique("test-brute-deferred");
  const auto assigner = makeAssigner(t, test::runtime(), techniqueParams(t, {{"test_knob", "5"}}, "--param"), &in.scene);
  const FrameResult ours = r.render(cam, *assigner, {t.pipeline, true});
  EXPECT_EQ(assigner->stats(), (std::vector<std::pair<std::string, double>>{{"test knob", 5.0}}));
  const auto brute = makeAssigner("deferred", test::runtime());
  const FrameResult ref = r.render(cam, *brute, {Pipeline::Deferred, true});
  EXPECT_EQ(ours.light_evaluations, ref.light_evaluations);
  EXPECT_EQ(ours.missed_lights, 0u);
}

// Values every spec must refuse, by type.
std::vector<std::string> badValues(const ParamSpec& p) {
  switch (p.type) {
    case ParamType::Count: {
      std::vector<std::string> v = {std::to_string(p.max + 1), "x", "-1"};
      const std::string below = std::to_string(p.min - 1);  // unless a word (cluster_tile's "0" = auto)
      if (p.min > 0 && std::find(p.choices.begin(), p.choices.end(), below) == p.choices.end()) v.push_back(below);
      return v;
    }
    case ParamType::Choice: return {"no-such-choice", ""};
    case ParamType::Switch: return {"maybe"};
    case ParamType::Text: return {"-1", ""};
  }
  return {};
}

void expectRefusedUpFront(const test::InProcessResult& r, const ParamSpec& p, const std::string& flag) {
  EXPECT_EQ(r.exit_code, 2) << r.out << r.err;
  EXPECT_EQ(r.out, "");  // no start-up line: nothing opened, loaded or rendered
  EXPECT_EQ(lines(r.err), 1) << r.err;
  EXPECT_TRUE(has(r.err, flag)) << r.err;
  EXPECT_TRUE(has(r.err, p.key + "=")) << r.err;
  EXPECT_TRUE(has(r.err, p.allowed())) << r.err;
}

TEST(TechniqueRegistry, EveryParameterRefusesOutOfRangeValuesBeforeAnything) {
  ASSERT_GE(registryParams().size(), 12u);  // 11 built-in keys and the test-only one
  for (const RegistryParam& rp : registryParams()) {
    const ParamSpec& p = rp.spec;
    for (const std::string& bad : badValues(p)) {
      SCOPED_TRACE(p.key + "=" + bad);
      ASSERT_FALSE(p.problem(bad).empty());
      // bench: a sweep whose first value is fine dies before its first run
      // (an empty item of a comma list is no value: bench drops it).
      if (!bad.empty()) {
        expectRefusedUpFront(
            runCliInProcess({"bench", "--size", "32x18", "--param", p.key + "=" + p.default_value + "," + bad}), p,
            "--param");
        expectRefusedUpFront(runCliInProcess({"bench", "--size", "32x18", p.renderFlag(), p.default_value + "," + bad}),
                             p, p.renderFlag());
      }
      if (p.type == ParamType::Switch) continue;  // render's switches take no value
      expectRefusedUpFront(runCliInProcess({"render", "--size", "32x18", p.renderFlag(), bad}), p, p.renderFlag());
    }
  }
}

TEST(TechniqueRegistry, SharedKeysAgreeAndDefaultsAreAccepted) {
  for (const TechniqueDescriptor* d : techniqueDescriptors()) {
    SCOPED_TRACE(d->family);
    EXPECT_FALSE(d->names.empty());
    EXPECT_TRUE(d->make);
    for (const ParamSpec& p : d->params) {
      EXPECT_EQ(p.problem(p.default_value), "") << p.key;
      EXPECT_TRUE(p.sameAs(findParam(p.key, "--param"))) << p.key;
    }
  }
  EXPECT_THROW(findParam("no_such_key", "--param"), UserError);
  EXPECT_THROW(registerTechnique(TechniqueDescriptor{}), std::logic_error);  // the registry was read already
}

TEST(TechniqueRegistry, RangesAreWhatTheTechniquesAccept) {
  const ParamSpec& tile = findParam("tile", "--param");
  EXPECT_EQ(tile.max, kMaxTileSize);
  EXPECT_NO_THROW(TileLightCuller(test::runtime(), tile.max, TileDepthMode::None));
  EXPECT_THROW(TileLightCuller(test::runtime(), tile.max + 1, TileDepthMode::None), UserError);
  const ParamSpec& cluster = findParam("cluster_tile", "--param");
  gpu::CameraParams cam{};
  cam.width = 64;
  cam.height = 36;
  cam.near_plane = 0.1f;
  cam.far_plane = 100.0f;
  cam.tan_half_fovy = 0.5f;
  cam.aspect = 64.0f / 36.0f;
  EXPECT_NO_THROW(ClusterGrid::make(cam, cluster.max));
  EXPECT_THROW(ClusterGrid::make(cam, cluster.max + 1), UserError);
}

}  // namespace
}  // namespace ml
