// What the technique benchmarks (tiled, clustered, hashed) share beyond
// BenchCommon.hpp, so that each bench main keeps only its own measurements:
//   BenchArgs + addBenchArgs()   --json, --reps, --device, --light-density
//   parseCommandLine()           argv, then --json and the bench's own checks,
//                                before GL/CL open (the vct bench uses it too)
//   BenchSetup::open()           GL + CL through the run layer (RunContext), the
//                                device lines, the default scene and its camera
//   generatedLights()            N lights in the default scene's light volumes
//   viewDepth()                  the default view's depth buffer at a resolution
//   runFrameSweep()              whole frames per technique through the run
//                                layer's timedRenders()/countedRender(): one
//                                median (summarize()), as `render` and `bench`
#pragma once

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <functional>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "host/run/SceneInputs.hpp"
#include "host/run/RunLayer.hpp"

namespace ml::benchutil {

// The options every technique bench takes.
struct BenchArgs {
  std::string json_path, device;
  int reps = 5;
  float light_density = 0.0f;
};
// `reps_help` says what a repetition is in this bench.
void addBenchArgs(CLI::App& app, BenchArgs& a, const char* reps_help = "timed repetitions (median reported)");

// The opening of a bench's run(): parses argv into `app` (--help and parse
// errors end the program as CLI11_PARSE ends it), then checks that --json can
// be written and runs `checks`, the bench's own flag checks (UserError), so
// that a bad flag fails before anything opens. Returns the exit code when the
// bench stops there, nothing when it goes on.
std::optional<int> parseCommandLine(CLI::App& app, int argc, char** argv, const BenchArgs& common,
                                    const std::function<void()>& checks = {});

// The default scene (data/default/) without its lights; lights come per case.
SceneInputs defaultScene();

struct BenchSetup {
  RunContext ctx;
  SceneInputs scene;  // defaultScene()
  const Camera& camera() const { return scene.cameras.frames.front(); }
  ClRuntime& cl() const { return *ctx.cl; }
  // Opens GL + CL on `device` and prints their two lines; `scene` as given.
  static BenchSetup open(const std::string& device, SceneInputs scene);
};

// `count` ("1000") lights generated in the default scene's light volumes
// (seed kThesisSeed), at constant density when `density` > 0, else of `radius` (0: the
// volumes' default).
std::vector<gpu::PointLight> generatedLights(const std::string& count, float density, float radius = 0.0f);

// "1280x720" -> (1280, 720); UserError naming `flag` otherwise.
std::pair<unsigned, unsigned> sizeOf(const std::string& text, const std::string& flag);
// Every item of a comma list of sizes, checked before GL/CL open.
void checkSizes(const std::string& list, const std::string& flag);

// The depth buffer (G-buffer, deferred convention) of the setup's camera at w x h.
std::vector<float> viewDepth(BenchSetup& b, unsigned w, unsigned h);

// A read-only device buffer holding `bytes` of `data`, at least `min_bytes` large.
cl::Buffer uploadBuffer(ClRuntime& cl, const void* data, std::size_t bytes, std::size_t min_bytes = 16);

// One technique of a frame sweep: a registered name and the parameters given to it.
struct FrameCase {
  std::string technique;
  std::vector<std::pair<std::string, std::string>> params;
};

struct FrameSweep {
  std::vector<std::string> sizes, lights;  // --frame-sizes, --frame-lights
  float light_density = 0.0f;
  std::vector<FrameCase> cases;
  int reps = 5;
  // true: one counted frame first (it also warms up), and the row adds
  // evaluations and the lower bound per covered pixel; false: one warm-up frame.
  bool counted = false;
};

// Per size, light count and case: `reps` timed frames of the setup's camera,
// one row each (per-pass medians, frame host time), one record each in `records`.
void runFrameSweep(BenchSetup& b, const FrameSweep& s, nlohmann::ordered_json& records);

// A scene folder of the thesis's suite where the tests look for it:
// $MANYLIGHTS_THESIS_SUITE/scenes/<name>, else the shared data folder next to
// the checkout (../shared/data/thesis-suite/scenes/<name>). No machine's path.
std::string thesisSuiteScene(const std::string& name);

}  // namespace ml::benchutil
