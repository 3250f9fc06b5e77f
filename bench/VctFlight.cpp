#include "VctFlight.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>

#include "BenchSupport.hpp"
#include "host/reference/IndirectReference.hpp"
#include "host/run/RunLayer.hpp"
#include "host/run/SceneInputs.hpp"
#include "host/techniques/Registry.hpp"
#include "host/util/DataPaths.hpp"
#include "host/util/Error.hpp"
#include "host/util/ThesisSeed.hpp"
#include "host/vct/VctGiPass.hpp"
#include "host/vct/VoxelCascade.hpp"

namespace ml::benchvct {
namespace {

constexpr const char* kTechnique = "deferred";
constexpr const char* kUpdatePasses[] = {"vct-voxelize", "vct-inject", "vct-fold", "vct-mips", "vct-textures"};

SceneInputs loadFlightScene(const std::string& name, const FlightOptions& o) {
  SceneInputArgs a;
  if (name != "default") {
    a.scene = benchutil::thesisSuiteScene(name);
    if (!std::filesystem::is_directory(a.scene))
      throw UserError("--flight-scenes: no scene folder " + a.scene + " (set MANYLIGHTS_THESIS_SUITE)");
    a.allow_missing_meshes = true;
  }
  a.resample = o.frames;
  return loadSceneInputs(a);
}

struct Config {
  std::string name;
  vct::VctGiSettings settings;
};

std::vector<Config> configs(const FlightOptions& o) {
  std::vector<Config> c(3);
  const unsigned big = std::min(2 * o.voxels, unsigned(ML_VOXEL_MAX_EDGE));
  c[0] = {"single " + std::to_string(o.voxels), {}};
  c[0].settings.grid = {o.voxels, vct::autoLevels(o.voxels), true};
  c[1] = {"cascade " + std::to_string(o.cascades) + "x" + std::to_string(o.voxels), c[0].settings};
  c[1].settings.cascades = o.cascades;
  c[2] = {"single " + std::to_string(big), {}};
  c[2].settings.grid = {big, vct::autoLevels(big), true};
  if (o.fold) {
    c.push_back({c[1].name + " fold", c[1].settings});
    c.back().settings.fold = true;
  }
  return c;
}

double updateMs(const PassTimings& p) {
  double ms = 0;
  for (const char* name : kUpdatePasses) {
    const double v = p.get(name);
    if (!PassTimings::isMissing(v)) ms += v;
  }
  return ms;
}

// One configuration's flight: the error at each sampled camera, and per frame
// the update's pass time and the voxels its scroll redid.
struct FlightRun {
  std::map<std::size_t, double> error;  // camera index -> noise-corrected rel RMSE
  std::vector<double> update_ms;        // per camera (0: the volume was reused)
  std::vector<std::size_t> scrolled;    // per camera, level-0 voxels redone by a scroll
  std::size_t bytes = 0;
};

FlightRun fly(RunContext& ctx, const SceneInputs& in, const vct::VctGiSettings& v,
              const std::map<std::size_t, IndirectImage>& refs, const FlightOptions& o) {
  FrameRenderer renderer(*ctx.cl, in.scene, o.width, o.height);
  renderer.setLights(in.lights);
  auto assigner = makeAssigner(kTechnique, *ctx.cl, &in.scene);
  vct::VctGiPass gi(*ctx.cl, v, in.scene.bounds);
  const FrameOptions options{findTechnique(kTechnique).pipeline, false, true, &gi};
  FlightRun run;
  std::size_t scrolled_before = 0;
  for (std::size_t i = 0; i < in.cameras.frames.size(); ++i) {
    const FrameResult r = renderer.render(in.cameras.frames[i], *assigner, options);
    run.update_ms.push_back(updateMs(r.passes));
    const std::size_t scrolled = gi.stats().json.value("vct_scrolled_voxels", std::size_t(0));
    run.scrolled.push_back(scrolled - scrolled_before);
    scrolled_before = scrolled;
    if (const auto ref = refs.find(i); ref != refs.end())
      run.error[i] = compareWithReference(gi.indirectRgba(), ref->second).corrected;
  }
  run.bytes = gi.stats().data_bytes;
  return run;
}

double median(std::vector<double> v) {
  if (v.empty()) return NAN;
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

std::map<std::size_t, IndirectImage> references(const SceneInputs& in, const FlightOptions& o) {
  std::map<std::size_t, IndirectImage> refs;
  const std::size_t n = in.cameras.frames.size();
  const std::size_t k = std::min<std::size_t>(std::max(1u, o.samples), n);
  const IndirectOptions r{o.reference_samples, kThesisSeed, false};
  for (std::size_t s = 0; s < k; ++s) {
    const std::size_t i = k == 1 ? 0 : s * (n - 1) / (k - 1);
    refs[i] = traceIndirectReference(in.scene, in.lights, in.cameras.frames[i], o.width, o.height, r);
  }
  return refs;
}

// The cascade's moves: each frame after the first whose update scrolled a
// level, its update time over the first frame's full build.
nlohmann::json moveCost(const FlightRun& c) {
  std::vector<double> ratios, ms;
  std::size_t voxels = 0;
  for (std::size_t i = 1; i < c.update_ms.size(); ++i)
    if (c.scrolled[i] > 0) {
      ratios.push_back(c.update_ms[i] / c.update_ms[0]);
      ms.push_back(c.update_ms[i]);
      voxels += c.scrolled[i];
    }
  return {{"full_build_ms", c.update_ms.front()},
          {"moves", ratios.size()},
          {"move_ms_median", ms.empty() ? nlohmann::json() : nlohmann::json(median(ms))},
          {"move_over_full_median", ratios.empty() ? nlohmann::json() : nlohmann::json(median(ratios))},
          {"move_over_full_max",
           ratios.empty() ? nlohmann::json() : nlohmann::json(*std::max_element(ratios.begin(), ratios.end()))},
          {"scrolled_voxels_mean", ratios.empty() ? 0.0 : double(voxels) / double(ratios.size())}};
}

// The folded cascade (--vct-fold) beside the plain one: where it is lower
// than the single grid, and its moves.
void foldSummary(nlohmann::json& summary, const std::string& name, const FlightRun& fold, const FlightRun& single,
                 const std::map<std::size_t, IndirectImage>& refs, const FlightOptions& o) {
  std::size_t wins = 0;
  for (const auto& [i, ref] : refs) wins += fold.error.at(i) < single.error.at(i);
  summary["fold_lower_at"] = wins;
  summary["fold_moves"] = moveCost(fold);
  const nlohmann::json& m = summary["fold_moves"];
  const auto value = [](const nlohmann::json& v) { return v.is_null() ? NAN : v.get<double>(); };
  std::printf("%s: the cascade with --vct-fold lower than the single %u^3 grid at %zu of %zu cameras; move / full "
              "build median %.3f, max %.3f\n",
              name.c_str(), o.voxels, wins, refs.size(), value(m["move_over_full_median"]),
              value(m["move_over_full_max"]));
}

nlohmann::json sceneFlight(RunContext& ctx, const std::string& name, const FlightOptions& o) {
  const SceneInputs in = loadFlightScene(name, o);
  const auto refs = references(in, o);
  const std::vector<Config> cs = configs(o);
  std::vector<FlightRun> runs;
  for (const Config& c : cs) runs.push_back(fly(ctx, in, c.settings, refs, o));
  std::printf("\n%s: %zu cameras, %zu lights, %ux%u; noise-corrected rel RMSE at %zu cameras\n", name.c_str(),
              in.cameras.frames.size(), in.lights.size(), o.width, o.height, refs.size());
  std::printf("%7s", "camera");
  for (const Config& c : cs) std::printf(" %16s", c.name.c_str());
  std::printf(" %14s\n", "cascade/single");
  nlohmann::json records = nlohmann::json::array();
  std::size_t wins = 0;
  for (const auto& [i, ref] : refs) {
    std::printf("%7zu", i);
    nlohmann::json j{{"scene", name}, {"camera", i}};
    for (std::size_t c = 0; c < cs.size(); ++c) {
      std::printf(" %16.4f", runs[c].error.at(i));
      j[cs[c].name] = runs[c].error.at(i);
    }
    const double ratio = runs[1].error.at(i) / runs[0].error.at(i);
    wins += ratio < 1.0;
    std::printf(" %14.3f\n", ratio);
    j["cascade_over_single"] = ratio;
    records.push_back(j);
  }
  nlohmann::json summary{{"scene", name}, {"summary", true}, {"cascade_lower_at", wins}, {"cameras", refs.size()}};
  for (std::size_t c = 0; c < cs.size(); ++c) summary[cs[c].name + " voxel_bytes"] = runs[c].bytes;
  summary["cascade_moves"] = moveCost(runs[1]);
  const nlohmann::json& m = summary["cascade_moves"];
  const auto number = [](const nlohmann::json& v, const char* f) {
    char b[32];
    if (v.is_null()) return std::string("n/a");
    std::snprintf(b, sizeof b, f, v.get<double>());
    return std::string(b);
  };
  std::printf("%s: cascade lower than the single %u^3 grid at %zu of %zu cameras; voxel memory MB %.1f / %.1f / "
              "%.1f; %zu camera moves scrolled a level: %s ms median (the first frame's full build %.1f ms), move / "
              "full build median %s, max %s, %.0f level-0 voxels redone per move\n",
              name.c_str(), o.voxels, wins, refs.size(), runs[0].bytes / 1e6, runs[1].bytes / 1e6,
              runs[2].bytes / 1e6, m["moves"].get<std::size_t>(), number(m["move_ms_median"], "%.1f").c_str(),
              m["full_build_ms"].get<double>(), number(m["move_over_full_median"], "%.3f").c_str(),
              number(m["move_over_full_max"], "%.3f").c_str(), m["scrolled_voxels_mean"].get<double>());
  if (cs.size() > 3) foldSummary(summary, name, runs[3], runs[0], refs, o);
  records.push_back(summary);
  return records;
}

}  // namespace

nlohmann::json flight(const FlightOptions& o) {
  vct::checkCascades(o.cascades);
  RunContext ctx = RunContext::open(DeviceChoice::resolve(o.device));
  ctx.printDevices();
  std::printf("\nVCT flight: %s frames, anisotropic, 9 cones, auto levels; error vs the Embree reference (%u "
              "samples/pixel) without its noise; the cascade's update passes (%s, %s, %s, %s, %s) per camera "
              "move\n",
              kTechnique, o.reference_samples, kUpdatePasses[0], kUpdatePasses[1], kUpdatePasses[2],
              kUpdatePasses[3], kUpdatePasses[4]);
  nlohmann::json all = nlohmann::json::array();
  for (const std::string& s : o.scenes)
    for (auto& r : sceneFlight(ctx, s, o)) all.push_back(r);
  return all;
}

}  // namespace ml::benchvct
