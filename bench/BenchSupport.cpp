#include "BenchSupport.hpp"

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <cstdio>

#include "BenchCommon.hpp"
#include "ml_build_paths.h"  // MANYLIGHTS_SOURCE_DIR (generated)
#include "gl/FrameRenderer.hpp"
#include "host/run/InputChecks.hpp"
#include "host/run/ImageSize.hpp"
#include "host/assign/BruteForceAssigner.hpp"
#include "host/run/SceneInputs.hpp"
#include "host/techniques/Registry.hpp"

namespace ml::benchutil {

void addBenchArgs(CLI::App& app, BenchArgs& a, const char* reps_help) {
  app.add_option("--json", a.json_path, "write records as JSON");
  app.add_option("--reps", a.reps, reps_help)->capture_default_str();
  app.add_option("--light-density", a.light_density, kLightDensityHelp)->check(finitePositive());
  app.add_option("--device", a.device, "OpenCL device");
}

std::optional<int> parseCommandLine(CLI::App& app, int argc, char** argv, const BenchArgs& common,
                                    const std::function<void()>& checks) {
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  }
  requireWritable("--json", common.json_path);
  if (checks) checks();
  return std::nullopt;
}

SceneInputs defaultScene() {
  SceneInputArgs base;
  base.lights = "1";
  return loadSceneInputs(base);
}

BenchSetup BenchSetup::open(const std::string& device, SceneInputs scene) {
  BenchSetup b{RunContext::open(DeviceChoice::resolve(device)), std::move(scene)};
  b.ctx.printDevices();
  return b;
}

std::vector<gpu::PointLight> generatedLights(const std::string& count, float density, float radius) {
  SceneInputArgs args;
  args.lights = count;
  args.light_radius = radius;
  args.light_density = density;
  return loadSceneInputs(args).lights;
}

std::pair<unsigned, unsigned> sizeOf(const std::string& text, const std::string& flag) {
  unsigned w = 0, h = 0;
  parseSize(text, flag, w, h);
  return {w, h};
}

void checkSizes(const std::string& list, const std::string& flag) {
  for (const auto& s : splitList(list)) (void)sizeOf(s, flag);
}

std::vector<float> viewDepth(BenchSetup& b, unsigned w, unsigned h) {
  FrameRenderer r(b.cl(), b.scene.scene, w, h);
  r.setLights({});
  BruteForceAssigner none;  // the G-buffer's depth does not depend on the lights' structure
  r.render(b.camera(), none, {Pipeline::Deferred, false, false});
  return r.targets().readDepth(true);
}

cl::Buffer uploadBuffer(ClRuntime& cl, const void* data, std::size_t bytes, std::size_t min_bytes) {
  cl::Buffer buf(cl.context(), CL_MEM_READ_ONLY, std::max(min_bytes, bytes));
  if (bytes) cl.queue().enqueueWriteBuffer(buf, CL_TRUE, 0, bytes, data);
  return buf;
}

namespace {

// One row of the sweep: `counted` holds the counted frame when the sweep counts.
void printFrameRow(const std::string& size, const std::string& lights, const std::string& tech, int tech_width,
                   const TimedFrame& t, const FrameResult* counted) {
  std::printf("%-11s %7s %-*s", size.c_str(), lights.c_str(), tech_width, tech.c_str());
  std::printf("%s", passListText(t.passes).c_str());
  if (!counted) {
    std::printf(" | frame=%.2f\n", t.host_ms);
    return;
  }
  const double px = double(std::max<std::uint64_t>(1, counted->covered_pixels));
  const double ratio = double(counted->light_evaluations) / double(std::max<std::uint64_t>(1, counted->lower_bound));
  std::printf(" | sum=%s | frame=%.2f evals/px=%.2f lb/px=%.2f ratio=%.3f\n", passTimeText(t.passes_total_ms, 2).c_str(),
              t.host_ms,
              counted->light_evaluations / px, counted->lower_bound / px, ratio);
}

nlohmann::ordered_json frameRecord(const std::string& size, const std::string& lights, const std::string& tech,
                                   unsigned w, unsigned h, const TimedFrame& t, const FrameResult* counted) {
  nlohmann::ordered_json passes;
  nlohmann::ordered_json clocks = nlohmann::ordered_json::object();
  for (std::size_t i = 0; i < t.passes.entries().size(); ++i) {
    const auto& [name, ms] = t.passes.entries()[i];
    passes[name] = PassTimings::isMissing(ms) ? nlohmann::ordered_json() : nlohmann::ordered_json(ms);  // never 0
    clocks[name] = t.passes.clockAt(i) == PassClock::Host ? "host" : "device";
  }
  const double seconds = t.host_ms * 1e-3;
  nlohmann::ordered_json rec = {{"name", "frame_" + tech}, {"resolution", size}, {"lights", std::stoul(lights)},
                                {"n", std::stoul(lights)}, {"seconds", seconds},
                                {"items_per_second", double(w) * h / seconds}, {"passes", passes},
                                {"pass_clocks", clocks}};
  if (counted) {
    const double px = double(std::max<std::uint64_t>(1, counted->covered_pixels));
    rec["sum_of_passes_ms"] = PassTimings::isMissing(t.passes_total_ms) ? nlohmann::ordered_json()
                                                                         : nlohmann::ordered_json(t.passes_total_ms);
    rec["evals_per_pixel"] = counted->light_evaluations / px;
    rec["lower_bound_per_pixel"] = counted->lower_bound / px;
    rec["evals_over_lower_bound"] =
        double(counted->light_evaluations) / double(std::max<std::uint64_t>(1, counted->lower_bound));
  }
  return rec;
}

}  // namespace

void runFrameSweep(BenchSetup& b, const FrameSweep& s, nlohmann::ordered_json& records) {
  int tech_width = 0;
  for (const auto& c : s.cases) tech_width = std::max(tech_width, int(c.technique.size()) + 1);
  for (const auto& size : s.sizes) {
    const auto [w, h] = sizeOf(size, "--frame-sizes");
    FrameRenderer r(b.cl(), b.scene.scene, w, h);
    for (const auto& ls : s.lights) {
      r.setLights(generatedLights(ls, s.light_density));
      for (const FrameCase& c : s.cases) {
        const TechniqueInfo& info = findTechnique(c.technique, "--frame-techniques");
        auto a = makeAssigner(info, b.cl(), techniqueParams(info, c.params, "--frame-techniques"), &b.scene.scene);
        FrameResult counted;
        if (s.counted) counted = countedRender(r, *a, {info.pipeline}, b.camera());
        else r.render(b.camera(), *a, {info.pipeline, false});
        const TimedFrame t = timedRenders(r, *a, {info.pipeline}, b.camera(), unsigned(std::max(s.reps, 1)));
        const FrameResult* cp = s.counted ? &counted : nullptr;
        printFrameRow(size, ls, c.technique, tech_width, t, cp);
        records.push_back(frameRecord(size, ls, c.technique, w, h, t, cp));
      }
    }
  }
}

std::string thesisSuiteScene(const std::string& name) {
  std::filesystem::path root = std::filesystem::path(MANYLIGHTS_SOURCE_DIR) / ".." / "shared" / "data" / "thesis-suite";
  if (const char* env = std::getenv("MANYLIGHTS_THESIS_SUITE"); env && *env) root = env;
  return (root / "scenes" / name).lexically_normal().string();
}

}  // namespace ml::benchutil
