#include "ml_build_paths.h"  // MANYLIGHTS_SOURCE_DIR (generated)
#include "host/app/BenchCommand.hpp"

#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <map>

#include "host/run/RunLayer.hpp"
#include "host/app/GiOptions.hpp"
#include "host/gi/Registry.hpp"
#include "host/run/InputChecks.hpp"
#include "host/app/InputFlags.hpp"
#include "host/app/RenderCommand.hpp"
#include "host/run/ImageSize.hpp"
#include "host/run/OutputFiles.hpp"
#include "host/bench/BenchRunner.hpp"
#include "host/cl/ClRuntime.hpp"
#include "host/scene/LightAnimator.hpp"
#include "host/util/Error.hpp"

namespace ml {
namespace fs = std::filesystem;
namespace {

std::string shellQuote(const std::string& s) {
  std::string q = "'";
  for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}


std::string utcNow() {
  const std::time_t t = std::time(nullptr);
  std::tm tm{};
  gmtime_r(&t, &tm);
  char buf[32];
  std::strftime(buf, sizeof buf, "%Y-%m-%dT%H:%M:%SZ", &tm);
  return buf;
}

std::string exeDir() {
  std::error_code ec;
  const fs::path p = fs::read_symlink("/proc/self/exe", ec);
  return ec ? std::string() : p.parent_path().string();
}

// "key=v1,v2" -> (key, {v1, v2}); later mentions of a key replace earlier ones.
void addSweep(ParamSweep& sweep, const std::string& key,
              const std::vector<std::string>& values) {
  for (auto& s : sweep)
    if (s.first == key) {
      s.second = values;
      return;
    }
  sweep.emplace_back(key, values);
}

// A CLI11 check refusing a list flag given with no items ("", ","), which
// would otherwise mean the flag's default (e.g. every technique).
CLI::Validator nonEmptyList(const std::string& expected) {
  return CLI::Validator(
      [expected](std::string& v) {
        return splitList(v).empty() ? "expected " + expected + ", got '" + v + "'" : std::string();
      },
      "LIST");
}

// Every output path can be written (folders made), before GL/CL open.
void checkBenchOutputs(const BenchArgs& a) {
  requireOutputFile("--json", a.json);
  requireOutputFile("--csv", a.csv);
  requireOutputDir("--plot", a.plot);
  requireOutputDir("--images", a.images);
}

bool isRegistryParam(const std::string& key) {
  for (const RegistryParam& p : registryParams())
    if (p.spec.key == key) return true;
  return false;
}

// The GI pass's descriptor of --gi (null for none); UserError for an unknown name.
const GiDescriptor* benchGi(const BenchArgs& a) {
  if (a.gi == "none") return nullptr;
  return &findGi(a.gi, "--gi");
}

// The technique variants of --techniques x the --param / --KEY sweeps, every
// value checked against its parameter's range; the keys of the GI pass
// (--gi) go to `gi`, every point of their product resolved by its table.
std::vector<TechniqueVariant> benchVariants(const BenchArgs& a, std::vector<GiVariant>& gi) {
  std::vector<std::string> tech_names = splitList(a.techniques);
  if (tech_names.empty())
    for (const auto& t : techniques()) tech_names.push_back(t.name);
  ParamSweep sweep;
  for (const auto& p : a.params) {
    const auto eq = p.find('=');
    if (eq == std::string::npos || eq == 0 || splitList(p.substr(eq + 1)).empty())
      throw UserError("--param: expected KEY=V1,V2,..., got '" + p + "'");
    addSweep(sweep, p.substr(0, eq), splitList(p.substr(eq + 1)));
  }
  for (const auto& [key, list] : a.shorthands) {
    const std::string flag = findParam(key, "--param").renderFlag();
    if (splitList(list).empty()) throw UserError(flag + ": expected a comma list");
    for (const auto& v : splitList(list)) checkParam(key, v, flag);
    addSweep(sweep, key, splitList(list));
  }
  const GiDescriptor* desc = benchGi(a);
  const ParamSweep gi_sweep = splitGiSweep(sweep, desc, giDescriptors(), "--param");
  gi = expandGiVariants(desc, gi_sweep, "--param");
  for (const auto& [key, values] : sweep)  // neither a technique's key nor the GI's: name both lists
    if (desc && !isRegistryParam(key)) {
      std::string keys;
      for (const ParamSpec& p : desc->params) keys += (keys.empty() ? "" : "|") + p.key;
      throw UserError("--param: unknown parameter '" + key + "' (neither a technique's nor --gi " + desc->name +
                      "'s: " + keys + ")");
    }
  return expandVariants(tech_names, sweep, "--param");
}

// "Parameter keys" of the help footer, from the registry.
std::string paramKeysHelp() {
  std::string s = "Parameter keys (--param KEY=V1,V2,..., repeatable, or --KEY V1,V2; each technique sweeps only the keys "
                  "it reads):\n";
  for (const RegistryParam& p : registryParams()) {
    std::string families;
    for (const auto& f : p.families) families += (families.empty() ? "" : ", ") + f;
    s += "  " + p.spec.key + " (" + p.spec.allowed() + "; default " + p.spec.default_value + "): " + families + "\n";
  }
  for (const GiDescriptor* d : giDescriptors()) {
    std::string gi_keys;
    for (const ParamSpec& p : d->params) gi_keys += (gi_keys.empty() ? "" : ", ") + p.key;
    s += "  with --gi " + d->name + " also its settings (as render's --gi " + d->name + " flags): " + gi_keys + "\n";
  }
  return s;
}

std::vector<const TechniqueInfo*> techniquesOf(const std::vector<TechniqueVariant>& variants) {
  std::vector<const TechniqueInfo*> techs;
  for (const auto& v : variants) techs.push_back(v.info);
  return techs;
}

// Light counts in the --lights list against the limits of every technique in
// the sweep, before any light is generated.
void checkLightCounts(const std::string& list, const std::vector<TechniqueVariant>& variants,
                      const std::string& flag) {
  for (const auto& item : splitList(list))
    if (std::uint64_t n = 0; parseLightCount(item, n)) checkLightLimits(flag, n, techniquesOf(variants), "generated");
}

// The same for the loaded light sets (files count too).
void checkLightSets(const std::vector<LightSetInput>& sets, const std::vector<TechniqueVariant>& variants,
                    const std::string& flag) {
  for (const auto& ls : sets) checkLightLimits(flag, ls.lights.size(), techniquesOf(variants), ls.label);
}

void printSummaries(const std::vector<RunSummary>& sums) {
  std::size_t w = 24;
  for (const auto& s : sums) w = std::max(w, s.run.size());
  const int W = static_cast<int>(w);
  bool any_counts = false, any_times = false;
  for (const auto& s : sums) {
    any_counts |= s.counted;
    any_times |= s.timed;
  }
  if (any_counts) {
    std::printf("\nlight evaluations per frame (exact lower bound: lights whose sphere contains the pixel's surface)\n");
    std::printf("%-*s %6s %14s %14s %14s %14s %14s %8s\n", W, "run", "frames", "mean", "median", "p95", "max",
                "bound mean", "/bound");
    for (const auto& s : sums) {
      if (!s.counted) continue;
      if (!s.shaded) {  // --no-shading: the bound only
        std::printf("%-*s %6zu %14s %14s %14s %14s %14.0f %8s\n", W, s.run.c_str(), s.frames, "-", "-", "-", "-",
                    s.lower_bound.mean, "-");
        continue;
      }
      std::printf("%-*s %6zu %14.0f %14.0f %14.0f %14.0f %14.0f %8.2f\n", W, s.run.c_str(), s.frames,
                  s.light_evaluations.mean, s.light_evaluations.median, s.light_evaluations.p95,
                  s.light_evaluations.max, s.lower_bound.mean,
                  s.lower_bound.mean > 0 ? s.light_evaluations.mean / s.lower_bound.mean : 0.0);
    }
  }
  if (any_times) {
    bool unshaded = false;
    for (const auto& s : sums) unshaded |= !s.shaded;
    std::printf("\nframe time, sum of device passes, ms (host wall in the last column)%s\n",
                unshaded ? "; --no-shading: depth and assignment passes only, no shading pass" : "");
    std::printf("%-*s %6s %10s %10s %10s %10s %10s %12s\n", W, "run", "frames", "mean", "median", "p95", "max",
                "host mean", "memory max");
    for (const auto& s : sums) {
      if (!s.timed) continue;
      std::printf("%-*s %6zu %10.3f %10.3f %10.3f %10.3f %10.3f %12.0f\n", W, s.run.c_str(), s.frames,
                  s.passes_total_ms.mean, s.passes_total_ms.median, s.passes_total_ms.p95, s.passes_total_ms.max,
                  s.host_ms.mean, s.memory_bytes.max);
    }
  }
}

// The JSON's "meta": the command, device, scene, camera and the plan.
nlohmann::ordered_json benchMeta(const BenchArgs& a, const RunScene& scene, const BenchPlan& plan,
                                 const RunContext& ctx) {
  const Camera& c0 = scene.cameras.frames.front();
  nlohmann::ordered_json meta;
  meta["command"] = a.command_line;
  meta["date"] = utcNow();
  meta["device"] = ctx.cl->info().name;
  meta["gl"] = ctx.gl->describe();
  nlohmann::ordered_json sj;
  sj["source"] = reportPath(scene.source);
  sj["format"] = scene.format;
  sj["name"] = scene.name;
  sj["triangles"] = scene.scene.triangleCount();
  sj["missing_meshes"] = scene.missing_meshes;
  meta["scene"] = sj;
  nlohmann::ordered_json cj;
  cj["fovy"] = c0.fovy_degrees;
  cj["near"] = c0.near_plane;
  cj["far"] = c0.far_plane;
  cj["path_frames"] = scene.cameras.frames.size();
  meta["camera"] = cj;
  meta["frames"] = plan.frames;
  nlohmann::ordered_json sz = nlohmann::ordered_json::array();
  for (const auto& [w, h] : plan.sizes) sz.push_back(std::to_string(w) + "x" + std::to_string(h));
  meta["sizes"] = sz;
  nlohmann::ordered_json lj = nlohmann::ordered_json::array();
  for (const auto& ls : plan.light_sets)
    lj.push_back({{"label", ls.label}, {"file", ls.file}, {"source", ls.source}, {"count", ls.lights.size()}});
  meta["light_sets"] = lj;
  nlohmann::ordered_json vj = nlohmann::ordered_json::array();
  for (const auto& v : plan.variants) {
    nlohmann::ordered_json p = nlohmann::ordered_json::object();
    for (const auto& [k, val] : v.labels) p[k] = val;
    vj.push_back({{"label", v.label}, {"technique", v.technique}, {"params", p}});
  }
  meta["variants"] = vj;
  meta["gi"] = a.gi;
  meta["gi_reference"] = a.gi_reference;
  if (a.gi_reference) meta["gi_reference_samples"] = a.gi_samples;
  meta["counts"] = plan.counts;
  meta["timing"] = plan.timing;
  meta["shading"] = plan.shade;
  meta["repeat"] = plan.repeat;
  meta["warmup"] = plan.warmup;
  meta["animate"] = plan.animate;
  meta["animate_speed"] = plan.animate_speed;

  return meta;
}

}  // namespace

std::string findPlotPython() {
  // An explicit choice is the only candidate; otherwise the PATH's python3
  // (which may be a virtualenv or pyenv shim without matplotlib) and then the
  // system one that the python3-matplotlib package installs into.
  std::vector<std::string> candidates;
  if (const char* env = std::getenv("MANYLIGHTS_PYTHON"); env && *env) candidates.push_back(env);
  else candidates = {"python3", "/usr/bin/python3"};
  for (const auto& c : candidates) {
    const std::string probe = shellQuote(c) + " -c 'import matplotlib' >/dev/null 2>&1";
    if (std::system(probe.c_str()) == 0) return c;
  }
  return {};
}

std::string plotScriptPath() {
  std::vector<fs::path> candidates;
  if (const char* env = std::getenv("MANYLIGHTS_PLOT_SCRIPT"); env && *env) candidates.emplace_back(env);
  candidates.emplace_back(fs::path(MANYLIGHTS_SOURCE_DIR) / "scripts" / "plot_bench.py");
  if (const std::string d = exeDir(); !d.empty()) candidates.emplace_back(fs::path(d) / ".." / "scripts" / "plot_bench.py");
  for (const auto& c : candidates)
    if (fs::is_regular_file(c)) return c.string();
  throw UserError("--plot: scripts/plot_bench.py not found (set MANYLIGHTS_PLOT_SCRIPT)");
}

void runPlotScript(const std::string& json_path, const std::string& out_dir) {
  const std::string script = plotScriptPath();
  const std::string python = findPlotPython();
  if (python.empty())
    throw UserError("--plot: no python3 with matplotlib found; install python3-matplotlib (or set MANYLIGHTS_PYTHON); "
                    "the results are in " + json_path);
  const std::string cmd =
      shellQuote(python) + " " + shellQuote(script) + " " + shellQuote(json_path) + " --out " + shellQuote(out_dir);
  std::fflush(stdout);
  const int status = std::system(cmd.c_str());
  if (status != 0)
    throw UserError("--plot: " + script + " failed (status " + std::to_string(status) + ") on " + json_path);
}

namespace {

// What a bench sweeps: light sets, techniques, sizes, frames, parameter values.
void addSweepFlags(CLI::App& cmd, BenchArgs& a) {
  cmd.add_option("--lights,--light-sets", a.scene.lights,
                 "light sets, comma-separated (see below; default: the scene's)")
      ->check(nonEmptyList("a comma list of light sets (leave the flag out for the scene's)"));
  cmd.add_option("--techniques", a.techniques, "comma list of: " + techniqueNames() + " (default: all)")
      ->check(nonEmptyList("a comma list of techniques (leave the flag out for all)"));
  cmd.add_option("--size", a.size, "WIDTHxHEIGHT")->capture_default_str();
  cmd.add_option("--sizes", a.sizes, "comma list of WIDTHxHEIGHT (resolution sweep; overrides --size)")
      ->check(nonEmptyList("a comma list of WIDTHxHEIGHT"));
  cmd.add_option("--frames", a.frames, "FIRST:LAST:STEP along the camera path, LAST inclusive (default: all)");
  cmd.add_option("--resample", a.scene.resample, "resample the camera path to N frames first (linear in eye/center/up)");
  cmd.add_option("--param,--params", a.params, "sweep KEY=V1,V2,... (repeatable; keys below)")->expected(1, -1);
  for (const RegistryParam& p : registryParams()) {
    const std::string key = p.spec.key;
    cmd.add_option_function<std::string>(
        p.spec.renderFlag(), [&a, key](const std::string& v) { a.shorthands[key] = v; },
        "shorthand for --param " + key + "=LIST");
  }
}

// How each frame is measured: repeats, warm-up, animation, counting, timing, shading.
void addMeasureFlags(CLI::App& cmd, BenchArgs& a) {
  cmd.add_option("--repeat", a.repeat, "timed renders per frame (per-pass median)")->capture_default_str();
  cmd.add_option("--warmup", a.warmup, "untimed renders before each run")->capture_default_str();
  cmd.add_option("--animate", a.animate,
                 "move this fraction of the lights (0..1) before every render of a frame; per-pass times then "
                 "include the structure update (hashed-update)")
      ->capture_default_str();
  cmd.add_option("--animate-speed", a.animate_speed, "--animate step per axis, times the light radius")
      ->capture_default_str();
  cmd.add_flag("--no-counts", a.no_counts, "skip the counting render (times only)");
  cmd.add_flag("--no-timing", a.no_timing, "skip the timed renders (counts only)");
  cmd.add_flag("--no-shading", a.no_shading, kNoShadingHelp);
}

// The GI pass in every frame and its reference.
void addBenchGiFlags(CLI::App& cmd, BenchArgs& a) {
  cmd.add_option("--gi", a.gi,
                 "none or a GI pass (" + giNames() + ") in every frame (its passes timed); --param also sweeps its "
                 "settings (render's flags of that pass)")
      ->capture_default_str();
  cmd.add_flag("--gi-reference", a.gi_reference,
               "with --gi: trace the ray-traced reference once per size, light set and frame; records get gi_rel_rmse");
  cmd.add_option("--gi-samples", a.gi_samples, "--gi-reference: hemisphere samples per pixel")->capture_default_str();
  cmd.add_option("--gi-seed", a.gi_seed, "--gi-reference: seed of the hemisphere samples")->capture_default_str();
}

}  // namespace

CLI::App* addBenchCommand(CLI::App& app, BenchArgs& a) {
  auto* cmd = app.add_subcommand(
      "bench",
      "Benchmark techniques over a scene's camera path: per-frame light evaluations, exact lower bound, pass times, "
      "memory; sweeps over techniques x light sets x resolutions x technique parameters; JSON/CSV/plots");
  cmd->footer(
      "Examples:\n"
      "  manylights bench --suite ../shared/data/thesis-suite/scenes/spaceship-indoor --allow-missing-meshes \\\n"
      "      --lights 70 --techniques deferred,tiled-deferred --param tile=8,16,32 --param tile_depth=none \\\n"
      "      --size 320x320 --frames 3:518:8 --json out/b.json --csv out/b.csv --plot out/plots\n"
      "  manylights bench --techniques forward,deferred --lights 256,1024 --sizes 320x180,640x360 --frames ::4\n"
      + paramKeysHelp() +
      "Light sets (--lights, comma list): JSON or .gltf/.glb files (their point lights); names under the suite's\n"
      "lights/; 'thesis' (the thesis's set per light count), 'all'; a count N (suite: the thesis's N-light set;\n"
      "glTF: N generated lights). Default: the scene folder's lights.json, else the glTF scene's own lights.\n" +
      std::string(kLightLimitsHelp));
  addInputFlags(*cmd, {kSceneFlag | kGenerateFlags | kSuiteFlags | kDeviceFlag | kProgressFlag | kWriteLightsFlag,
                       &a.scene, &a.device, &a.progress});
  addSweepFlags(*cmd, a);
  addMeasureFlags(*cmd, a);
  cmd->add_option("--json", a.json, "write per-frame records and per-run summaries as JSON");
  cmd->add_option("--csv", a.csv, "write per-frame records as CSV");
  cmd->add_option("--plot", a.plot, "render thesis-style figures (PNG) into this folder (python3-matplotlib)");
  cmd->add_option("--images", a.images, "write every record's shaded image (PNG) into this folder");
  addBenchGiFlags(*cmd, a);
  cmd->add_option("--fovy", a.fovy, "override the camera's vertical field of view, degrees (suite: 45)");
  cmd->add_option("--near", a.near_plane, "override the near plane (suite: 0.01)");
  cmd->add_option("--far", a.far_plane, "override the far plane (suite: 4000)");
  return cmd;
}

namespace {

// --gi's combinations with the other flags (its settings are checked by benchVariants).
void checkBenchGiFlags(const BenchArgs& a) {
  if (a.gi_reference && !(benchGi(a) && benchGi(a)->reference_shadows))
    throw UserError("--gi-reference: only with a --gi pass that a reference can check");
  if (a.gi_samples == 0 || a.gi_samples > kMaxGiSamples)
    throw UserError("--gi-samples: expected 1.." + std::to_string(kMaxGiSamples) + ", got " +
                    std::to_string(a.gi_samples));
  if (a.gi == "none") return;
  if (a.no_shading) throw UserError("--gi: the indirect light is added to the shaded image; not with --no-shading");
  if (a.no_timing) throw UserError("--gi: the GI pass runs in the timed renders; not with --no-timing");
  if (a.gi_reference && a.animate > 0)
    throw UserError("--gi-reference: the reference sees the lights as loaded; not with --animate");
}

// What runBench takes from the flags, all checked before anything loads.
struct CheckedBenchFlags {
  std::vector<std::pair<unsigned, unsigned>> sizes;
  std::vector<TechniqueVariant> variants;
  std::vector<GiVariant> gi;
  FrameRange range;
  Progress::Mode progress = Progress::Mode::Auto;
  DeviceChoice device;
};

CheckedBenchFlags checkBenchFlags(const BenchArgs& a, const std::string& where) {
  CheckedBenchFlags c;
  for (const auto& s : a.sizes.empty() ? std::vector<std::string>{a.size} : splitList(a.sizes)) {
    unsigned w = 0, h = 0;
    parseSize(s, a.sizes.empty() ? "--size" : "--sizes", w, h);
    c.sizes.emplace_back(w, h);
  }
  if (c.sizes.empty()) throw UserError("--sizes: no sizes given");
  c.variants = benchVariants(a, c.gi);
  checkBenchGiFlags(a);
  c.range = a.frames.empty() ? FrameRange{} : parseFrameRange(a.frames, "--frames");
  c.progress = Progress::parseMode(a.progress, "--progress");
  (void)LightAnimator({}, a.animate, kThesisSeed, a.animate_speed);  // validates --animate, --animate-speed
  if (a.no_counts && a.no_timing) throw UserError("--no-counts and --no-timing together leave nothing to measure");
  if (a.no_shading && !a.images.empty()) throw UserError("--images: there is no shaded image with --no-shading");
  if (!a.plot.empty() && findPlotPython().empty())
    throw UserError("--plot: no python3 with matplotlib found; install python3-matplotlib (or set MANYLIGHTS_PYTHON)");
  if (a.fovy != 0 && !(a.fovy > 0 && a.fovy < 180)) throw UserError("--fovy: must be in (0, 180) degrees");
  if (a.near_plane < 0 || a.far_plane < 0) throw UserError("--near/--far: must be positive");
  checkBenchOutputs(a);
  checkWriteLightsFlag(a.scene.write_lights);
  checkLightCounts(a.scene.lights, c.variants, where);
  c.device = DeviceChoice::resolve(a.device);
  return c;
}

// The scene's inputs with the lens overrides (--fovy, --near, --far) applied.
SceneInputArgs benchSceneArgs(const BenchArgs& a) {
  SceneInputArgs sa = a.scene;
  if (a.fovy > 0) sa.fovy = a.fovy;
  if (a.near_plane > 0) sa.near_plane = a.near_plane;
  if (a.far_plane > 0) sa.far_plane = a.far_plane;
  return sa;
}

BenchPlan benchPlan(const BenchArgs& a, const CheckedBenchFlags& c, const RunScene& scene, const std::string& where) {
  BenchPlan plan;
  plan.variants = c.variants;
  plan.gi = c.gi;
  plan.gi_reference_samples = a.gi_reference ? a.gi_samples : 0;
  plan.gi_reference_seed = a.gi_seed;
  plan.light_sets = resolveLightSets(scene, benchSceneArgs(a), where);
  checkLightSets(plan.light_sets, c.variants, where);
  if (!a.scene.write_lights.empty() && plan.light_sets.size() != 1)
    throw UserError("--write-lights: writes one light set, the sweep has " + std::to_string(plan.light_sets.size()) +
                    " (give one --lights set)");
  plan.sizes = c.sizes;
  plan.frames = selectFrames(c.range, scene.cameras.frames.size(), "--frames");
  plan.counts = !a.no_counts;
  plan.timing = !a.no_timing;
  plan.shade = !a.no_shading;
  plan.repeat = std::max(a.repeat, 1u);
  plan.warmup = a.warmup;
  plan.image_dir = a.images;
  plan.animate = a.animate;
  plan.animate_speed = a.animate_speed;
  return plan;
}

void printBenchHeader(const RunContext& ctx, const RunScene& scene, const BenchPlan& plan) {
  const Camera& c0 = scene.cameras.frames.front();
  ctx.printDevices();
  std::printf("scene: %s [%s] (%zu triangles, %zu camera frames; fovy %g, near %g, far %g)\n",
              reportPath(scene.source).c_str(), scene.format.c_str(), scene.scene.triangleCount(),
              scene.cameras.frames.size(), c0.fovy_degrees, c0.near_plane, c0.far_plane);
  if (!scene.missing_meshes.empty()) {
    std::string m;
    for (const auto& id : scene.missing_meshes) m += (m.empty() ? "" : ", ") + id;
    std::printf("missing meshes (skipped): %s\n", m.c_str());
  }
  std::printf("%zu technique variant(s) x %zu GI variant(s) x %zu light set(s) x %zu size(s) x %zu frame(s) = %zu "
              "records\n",
              plan.variants.size(), plan.gi.size(), plan.light_sets.size(), plan.sizes.size(), plan.frames.size(),
              planSteps(plan));
  std::fflush(stdout);
}

// --gi-reference: each record's relative RMSE of the indirect image and its voxel memory.
void printGiErrors(const std::vector<FrameRecord>& records) {
  bool any = false;
  for (const auto& r : records) {
    if (r.gi_rel_rmse < 0) continue;
    if (!any)
      std::printf("\ngi vs reference: relative RMSE of the indirect image (covered pixels), the reference's own "
                  "noise, the error without it, voxel MB\n");
    any = true;
    std::printf("%s frame %zu: %.4f %.4f %.4f %10.1f\n", r.run.c_str(), r.frame, r.gi_rel_rmse, r.gi_ref_noise,
                r.gi_rel_rmse_corrected, double(r.voxel_bytes) / 1048576.0);
  }
}

// Runs the plan, writing JSON/CSV: results so far go to <file>.partial after
// every finished run (meta "complete": false), so an interrupted sweep still
// leaves usable files that do not pass for a whole run; the named files
// appear, atomically, only when every record is in, and the .partial files go.
std::vector<FrameRecord> runAndWrite(const BenchArgs& a, const RunContext& ctx, const RunScene& scene,
                                     const BenchPlan& plan, Progress::Mode progress_mode,
                                     const std::string& json_path) {
  nlohmann::ordered_json meta = benchMeta(a, scene, plan, ctx);
  auto save = [&](const std::vector<FrameRecord>& recs, bool complete) {
    const auto sums = summarizeRuns(recs);
    const std::string suffix = complete ? "" : ".partial";
    meta["complete"] = complete;
    meta["records_planned"] = planSteps(plan);
    if (!json_path.empty())
      writeFileAtomically(a.json.empty() ? "--plot" : "--json", json_path + suffix,
                          benchJson(meta, recs, sums).dump(1) + "\n");
    if (!a.csv.empty()) writeFileAtomically("--csv", a.csv + suffix, benchCsv(recs));
  };
  std::vector<FrameRecord> so_far;
  Progress progress(planSteps(plan), progress_mode);
  const std::size_t frames_per_run = plan.frames.size();
  const auto records = runBench(*ctx.cl, scene, plan, &progress, [&](const FrameRecord& r) {
    so_far.push_back(r);
    if (so_far.size() % frames_per_run == 0 && so_far.size() < planSteps(plan)) save(so_far, false);
  });
  progress.finish();
  save(records, true);
  for (const std::string& p : {json_path, a.csv}) {
    std::error_code ec;
    if (!p.empty()) fs::remove(p + ".partial", ec);
  }
  return records;
}

}  // namespace

int runBench(const BenchArgs& a) {
  const std::string where = "--lights";
  // Everything that can be checked without rendering is checked first.
  const CheckedBenchFlags checked = checkBenchFlags(a, where);
  const RunScene scene = loadRunScene(benchSceneArgs(a));
  const Camera& c0 = scene.cameras.frames.front();
  if (!(c0.far_plane > c0.near_plane)) throw UserError("--near/--far: far must exceed near");
  const BenchPlan plan = benchPlan(a, checked, scene, where);

  const RunContext ctx = RunContext::open(checked.device);
  for (const auto& ls : plan.light_sets) checkDeviceLightLimits(where, ls.lights.size(), ctx.cl->info());
  printBenchHeader(ctx, scene, plan);
  std::string json_path = a.json;
  if (json_path.empty() && !a.plot.empty()) json_path = (fs::path(a.plot) / "bench.json").string();
  const auto records = runAndWrite(a, ctx, scene, plan, checked.progress, json_path);
  printSummaries(summarizeRuns(records));
  printGiErrors(records);
  if (!json_path.empty()) std::printf("\nwrote %s\n", json_path.c_str());
  if (!a.csv.empty()) std::printf("wrote %s\n", a.csv.c_str());
  if (!a.scene.write_lights.empty()) {
    writeLightsGltf(a.scene.write_lights, plan.light_sets.front().lights);
    std::printf("wrote %s (%zu lights)\n", a.scene.write_lights.c_str(), plan.light_sets.front().lights.size());
  }
  if (!a.plot.empty()) {
    runPlotScript(json_path, a.plot);
    std::printf("wrote plots to %s\n", a.plot.c_str());
  }
  return 0;
}

}  // namespace ml
