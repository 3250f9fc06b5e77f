#include "host/app/RenderCommand.hpp"

#include <nlohmann/json.hpp>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <cstdio>
#include <random>

#include "gl/FrameRenderer.hpp"
#include "host/run/RunLayer.hpp"
#include "host/run/InputChecks.hpp"
#include "host/app/InputFlags.hpp"
#include "host/run/ImageSize.hpp"
#include "host/run/OutputFiles.hpp"
#include "host/cl/ClRuntime.hpp"
#include "host/scene/LightAnimator.hpp"
#include "host/util/Error.hpp"
#include "host/util/Heatmap.hpp"
#include "host/util/ImageIO.hpp"

namespace ml {

namespace {

std::string joined(const std::vector<std::string>& list, const char* sep) {
  std::string s;
  for (const auto& x : list) s += (s.empty() ? "" : sep) + x;
  return s;
}

std::string paramHelp(const RegistryParam& p) {
  return joined(p.families, ", ") + ": " + p.spec.help + " (" + p.spec.allowed() + "; default " +
         p.spec.default_value + ")";
}

}  // namespace

void addTechniqueFlags(CLI::App& cmd, std::map<std::string, std::string>& params,
                       std::map<std::string, std::string>* views) {
  for (const RegistryParam& p : registryParams()) {
    const std::string key = p.spec.key, flag = p.spec.renderFlag();
    if (p.spec.type == ParamType::Switch) {
      cmd.add_flag_callback(flag, [&params, key] { params[key] = "on"; }, paramHelp(p));
      cmd.add_flag_callback("--no-" + flag.substr(2), [&params, key] { params[key] = "off"; },
                            "the opposite of " + flag);
    } else {
      cmd.add_option_function<std::string>(flag, [&params, key](const std::string& v) { params[key] = v; },
                                           paramHelp(p));
    }
  }
  if (!views) return;
  for (const TechniqueDescriptor* d : techniqueDescriptors())
    for (const DebugViewSpec& v : d->debug_views) {
      const std::string name = v.name;
      cmd.add_option_function<std::string>(v.flag(), [views, name](const std::string& f) { (*views)[name] = f; },
                                           d->family + ": " + v.help);
    }
}

CLI::App* addRenderCommand(CLI::App& app, RenderArgs& a) {
  auto* cmd = app.add_subcommand("render", "Render one frame with one technique; print per-pass times and counts");
  addInputFlags(*cmd, {kSceneInputFlags | kSuiteFlags | kDeviceFlag | kWriteLightsFlag, &a.inputs, &a.device});
  cmd->footer(kLightLimitsHelp);
  cmd->add_option("--technique", a.technique, "one of: " + techniqueNames())->capture_default_str();
  cmd->add_option("--size", a.size, "WIDTHxHEIGHT")->capture_default_str();
  cmd->add_option("--frame", a.frame, "index into the camera path")->capture_default_str();
  cmd->add_option("--frames", a.frames, "timed frames (median reported)")->capture_default_str();
  cmd->add_option("--warmup", a.warmup, "untimed frames first")->capture_default_str();
  cmd->add_option("--out", a.out, "output image (.png 8-bit, .exr float; other extensions are refused)");
  cmd->add_option("--heatmap", a.heatmap,
                  "write a heat map of lights evaluated per pixel (cubehelix) to this PNG, its colour bar and scale "
                  "under the image");
  cmd->add_option("--heatmap-max", a.heatmap_max, "count mapped to the top of the palette (default: frame max)");
  cmd->add_option("--ratio-map", a.ratio_map,
                  "write lights evaluated / lights in range (the exact lower bound) per pixel to this PNG: 1x up to "
                  "--ratio-max in viridis, grey where no light is in range, its colour bar and scale under the image");
  cmd->add_option("--ratio-max", a.ratio_max, "ratio mapped to the top of the --ratio-map palette (above 1)")
      ->capture_default_str();
  cmd->add_flag("--counts", a.counts, "count light evaluations and the exact lower bound (extra frame)");
  cmd->add_option("--stats-json", a.stats_json, "write times and counts as JSON (implies --counts)");
  cmd->add_flag("--no-shading", a.no_shading, kNoShadingHelp);
  cmd->add_option("--animate", a.animate,
                  "move this fraction of the lights (0..1) before every timed frame (hashed: incremental update)");
  cmd->add_option("--animate-speed", a.animate_speed,
                  "--animate step per axis, times the light radius (lights stay within twice that of their start)")
      ->capture_default_str();
  addGiFlags(*cmd, a.gi);
  addTechniqueFlags(*cmd, a.params, &a.views);
  return cmd;
}

namespace {

// Flags checked before any input is loaded (InputChecks.hpp): technique
// parameters and debug views against the registry, output paths (writable,
// image extensions), a generated light count against the technique's and the
// memory limits.
void checkRenderFlags(const RenderArgs& a, const TechniqueInfo& tech) {
  for (const auto& [key, value] : a.params) checkParam(key, value, findParam(key, "--param").renderFlag());
  if (a.frames == 0) throw UserError("--frames: must be at least 1");
  (void)LightAnimator({}, a.animate, kThesisSeed, a.animate_speed);  // validates --animate and --animate-speed
  for (const auto& [view, file] : a.views) {
    const std::string flag = DebugViewSpec{view, ""}.flag();
    bool offered = false;
    for (const DebugViewSpec& v : tech.descriptor->debug_views) offered |= v.name == view;
    if (!offered) throw UserError(flag + ": not a view of technique '" + tech.name + "'");
    requireImageFile(flag, file);
  }
  requireImageFile("--out", a.out);
  requireImageFile("--heatmap", a.heatmap);
  requireImageFile("--ratio-map", a.ratio_map);
  if (!(a.ratio_max > 1.0 && a.ratio_max <= 1e6))
    throw UserError("--ratio-max: expected a ratio above 1 (up to 1e6), got " + std::to_string(a.ratio_max));
  if (a.no_shading && !a.out.empty()) throw UserError("--out: there is no shaded image with --no-shading");
  if (a.no_shading && giPassOf(a.gi))
    throw UserError("--gi: " + a.gi.mode + " adds to the shaded image; there is none with --no-shading");
  for (const auto& [flag, file] : {std::pair{"--heatmap", &a.heatmap}, std::pair{"--ratio-map", &a.ratio_map}})
    if (a.no_shading && !file->empty())
      throw UserError(std::string(flag) + ": light evaluations are not counted with --no-shading");
  requireOutputFile("--stats-json", a.stats_json);
  checkWriteLightsFlag(a.inputs.write_lights);
  checkGiFlags(a.gi, a.out);
  std::uint64_t count = 0;
  if (parseLightCount(a.inputs.lights, count)) checkLightLimits("--lights", count, {&tech}, "generated");
}

std::vector<std::pair<std::string, std::string>> givenParams(const RenderArgs& a) {
  return {a.params.begin(), a.params.end()};
}

// What one render run measured.
struct RenderRun {
  TimedFrame timed;
  FrameResult counted;
  bool has_counts = false;
  std::size_t animated_per_frame = 0;
  std::vector<std::pair<std::string, double>> stats;
  GiResult gi;
};

void printTimes(const TimedFrame& t) {
  if (!t.shaded) std::printf("\nno shading pass (--no-shading): depth and light assignment only\n");
  std::printf("\n%-24s %10s\n", "pass", "ms (median)");
  for (std::size_t i = 0; i < t.passes.entries().size(); ++i) {
    const auto& [name, ms] = t.passes.entries()[i];
    std::printf("%-24s %10s%s\n", name.c_str(), passTimeText(ms).c_str(),
                t.passes.clockAt(i) == PassClock::Host ? " (host)" : "");
  }
  std::printf("%-24s %10s\n", "sum of passes", passTimeText(t.passes_total_ms).c_str());
  std::printf("%-24s %10.3f\n", "frame (host wall)", t.host_ms);
  if (t.passes.anyHost())
    std::printf("(host): timed on the host clock (a GL/CL hand-over, or a device whose own clock is unusable: the "
                "pass bracketed by finish calls)\n");
  if (t.passes.anyMissing()) std::printf("n/a: the device gave no usable time for the pass\n");
}

void printCounts(const FrameResult& c) {
  const double per_px = c.covered_pixels ? double(c.light_evaluations) / c.covered_pixels : 0.0;
  const double lb_px = c.covered_pixels ? double(c.lower_bound) / c.covered_pixels : 0.0;
  auto u = [](std::uint64_t v) { return static_cast<unsigned long long>(v); };
  if (!c.shaded) {
    std::printf("\nlight evaluations   %14s  (not counted: no shading pass)\n", "-");
    std::printf("exact lower bound   %14llu  (%.2f per covered pixel)\n", u(c.lower_bound), lb_px);
    std::printf("covered pixels      %14llu\n", u(c.covered_pixels));
    return;
  }
  std::printf("\nlight evaluations   %14llu  (%.2f per covered pixel)\n", u(c.light_evaluations), per_px);
  std::printf("exact lower bound   %14llu  (%.2f per covered pixel)\n", u(c.lower_bound), lb_px);
  std::printf("missed lights       %14llu  (bound lights not evaluated: must be 0)\n", u(c.missed_lights));
  std::printf("ratio to bound      %14.3f\n", c.lower_bound ? double(c.light_evaluations) / c.lower_bound : 0.0);
  std::printf("covered pixels      %14llu\n", u(c.covered_pixels));
  std::printf("fragment evaluations%14llu  (all shaded fragments, overdraw included)\n", u(c.fragment_evaluations));
}

// A heat map with its colour bar; prints the scale used.
void writeHeatmap(const std::string& flag, const std::string& file, const TechniqueInfo& tech,
                  const FrameRenderer& r, HeatmapScale scale) {
  const FrameHeatmap map = frameHeatmap(r, tech.pipeline, scale);
  writeImageAtomically(flag, file, r.width(), r.height() + colourBarRows(r.width()), 4,
                       withColourBar(map.rgba, r.width(), r.height(), map.scale));
  if (scale.kind == HeatmapKind::Ratio)
    std::printf("ratio map scale: 1x..%gx lights evaluated / lights in range (colour bar under the image)\n",
                map.scale.top);
  else
    std::printf("heat map scale: 0..%.0f lights evaluated per pixel (colour bar under the image)\n", map.scale.top);
}

// Warm-up, the timed frames (animated), then the counting frame and the
// images that need it.
RenderRun renderFrames(const RenderArgs& a, const TechniqueInfo& tech, const SceneInputs& inputs,
                       FrameRenderer& renderer, LightAssigner& assigner, GiPass* gi) {
  const Camera& camera = inputs.cameras.frames[a.frame];
  const FrameOptions options{tech.pipeline, false, !a.no_shading, gi};
  for (unsigned i = 0; i < a.warmup; ++i) renderer.render(camera, assigner, options);
  LightAnimator animator(inputs.lights, a.animate, kThesisSeed, a.animate_speed);
  RenderRun run;
  run.animated_per_frame = animator.movesPerStep();
  if (a.animate > 0.0)
    std::printf("animate: %zu of %zu lights move before each timed frame (step %g r)\n", animator.movesPerStep(),
                inputs.lights.size(), a.animate_speed);
  run.timed = timedRenders(renderer, assigner, options, camera, a.frames, [&] {
    if (animator.movesPerStep() > 0) renderer.setLights(animator.step());
  });
  if (!a.out.empty())
    writeImageAtomically("--out", a.out, renderer.width(), renderer.height(), 4, renderer.targets().readColor());
  printTimes(run.timed);
  run.has_counts = a.counts || !a.stats_json.empty() || !a.heatmap.empty() || !a.ratio_map.empty();
  if (run.has_counts) {
    run.counted = countedRender(renderer, assigner, options, camera);
    if (!a.heatmap.empty())
      writeHeatmap("--heatmap", a.heatmap, tech, renderer, {HeatmapKind::Evaluated, double(a.heatmap_max)});
    if (!a.ratio_map.empty()) writeHeatmap("--ratio-map", a.ratio_map, tech, renderer, {HeatmapKind::Ratio, a.ratio_max});
    printCounts(run.counted);
  }
  for (const auto& [view, file] : a.views) {
    const std::string flag = DebugViewSpec{view, ""}.flag();
    writeImageAtomically(flag, file, renderer.width(), renderer.height(), 4,
                         frameDebugView(renderer, tech.pipeline, camera, assigner, view));
    std::printf("wrote %s\n", file.c_str());
  }
  run.stats = assigner.stats();
  return run;
}

// The pass's own fields (GiPass::stats), then the reference's.
void writeGiStats(const GiArgs& a, const GiResult& gi, nlohmann::ordered_json& j) {
  for (const auto& [key, value] : gi.stats.json.items()) j[key] = value;
  if (!gi.has_reference) return;
  j["gi_samples"] = a.samples;
  j["gi_shadows"] = giShadows(a);
  j["gi_bounces"] = a.bounces;
  j["gi_reference_ms"] = gi.ms;
  j["gi_reference_cached"] = gi.reference_cached;
  if (gi.has_pass) {
    const std::string bounces = a.bounces == 1 ? "one bounce" : std::to_string(a.bounces) + " bounces";
    j["gi_reference_transport"] = giShadows(a) == "ray"
                                      ? bounces + ", diffuse; visibility of the lights from the bounce points "
                                                  "(--gi-shadows ray)"
                                      : bounces + ", diffuse; no visibility in the bounce light (--gi-shadows none)";
    j["gi_rel_rmse"] = gi.error.error.rel_rmse;
    j["gi_rel_rmse_pixels"] = gi.error.error.pixels;
    // The reference's own noise and the error without it (null: no estimate, 1 sample).
    j["gi_ref_noise"] = gi.error.ref_noise >= 0 ? nlohmann::ordered_json(gi.error.ref_noise) : nlohmann::ordered_json();
    j["gi_rel_rmse_corrected"] =
        gi.error.corrected >= 0 ? nlohmann::ordered_json(gi.error.corrected) : nlohmann::ordered_json();
  }
}

void writeStatsJson(const RenderArgs& a, const TechniqueInfo& tech, const SceneInputs& inputs, const RenderRun& run,
                    const RunContext& ctx, unsigned width, unsigned height) {
  nlohmann::ordered_json j;
  j["technique"] = tech.name;
  j["width"] = width;
  j["height"] = height;
  j["lights"] = inputs.lights.size();
  j["lights_source"] = inputs.lights_source;
  j["lights_file"] = inputs.lights_file.empty() ? nlohmann::ordered_json() : nlohmann::ordered_json(inputs.lights_file);
  j["frame"] = a.frame;
  j["timed_frames"] = a.frames;
  j["animate"] = a.animate;
  j["animated_lights_per_frame"] = run.animated_per_frame;
  nlohmann::ordered_json passes = nlohmann::ordered_json::object();
  nlohmann::ordered_json clocks = nlohmann::ordered_json::object();
  for (std::size_t i = 0; i < run.timed.passes.entries().size(); ++i) {
    const auto& [name, ms] = run.timed.passes.entries()[i];
    passes[name] = PassTimings::isMissing(ms) ? nlohmann::ordered_json() : nlohmann::ordered_json(ms);
    clocks[name] = run.timed.passes.clockAt(i) == PassClock::Host ? "host" : "device";
  }
  j["passes"] = passes;  // null: the device gave no usable time
  j["pass_clocks"] = clocks;  // "host": bracketed by finish calls, the device clock unusable
  j["frame_host_ms"] = run.timed.host_ms;
  const bool shaded = !a.no_shading;
  auto evals = [&](std::uint64_t v) { return shaded ? nlohmann::ordered_json(v) : nlohmann::ordered_json(); };
  j["shaded"] = shaded;
  j["light_evaluations"] = evals(run.counted.light_evaluations);
  j["lower_bound"] = run.counted.lower_bound;
  j["missed_lights"] = evals(run.counted.missed_lights);
  j["covered_pixels"] = run.counted.covered_pixels;
  j["fragment_evaluations"] = evals(run.counted.fragment_evaluations);
  j["memory_bytes"] = run.counted.memory_bytes;
  nlohmann::ordered_json st = nlohmann::ordered_json::object();
  for (const auto& [k, v] : run.stats) st[k] = v;
  j["technique_stats"] = st;
  j["gi"] = a.gi.mode;
  writeGiStats(a.gi, run.gi, j);
  j["device"] = ctx.cl->info().name;
  j["gl"] = ctx.gl->describe();
  writeFileAtomically("--stats-json", a.stats_json, j.dump(2) + "\n");
}

}  // namespace

int runRender(const RenderArgs& a) {
  unsigned width = 0, height = 0;
  parseSize(a.size, "--size", width, height);
  const TechniqueInfo& tech = findTechnique(a.technique);
  checkRenderFlags(a, tech);
  const ParamValues params = techniqueParams(tech, givenParams(a), "--param");
  const DeviceChoice device = DeviceChoice::resolve(a.device);

  const SceneInputs inputs = loadSceneInputs(a.inputs);
  if (a.frame >= inputs.cameras.frames.size())
    throw UserError("--frame: " + std::to_string(a.frame) + " is past the camera path's " +
                    std::to_string(inputs.cameras.frames.size()) + " frames");
  checkLightLimits("--lights", inputs.lights.size(), {&tech}, a.inputs.lights.empty() ? "default" : a.inputs.lights);

  const RunContext ctx = RunContext::open(device);
  checkDeviceLightLimits("--lights", inputs.lights.size(), ctx.cl->info());
  ctx.printDevices();
  std::printf("scene: %s (%zu triangles) | lights: %s | %ux%u | technique: %s\n", reportPath(inputs.scene.source).c_str(),
              inputs.scene.triangleCount(), inputs.lights_label.c_str(), width, height, tech.name.c_str());

  FrameRenderer renderer(*ctx.cl, inputs.scene, width, height);
  renderer.setLights(inputs.lights);
  auto assigner = makeAssigner(tech, *ctx.cl, params, &inputs.scene);
  const std::unique_ptr<GiPass> gi = makeFrameGiPass(a.gi, *ctx.cl, inputs.scene);
  RenderRun run = renderFrames(a, tech, inputs, renderer, *assigner, gi.get());
  run.gi = runGi(a.gi, inputs, inputs.cameras.frames[a.frame], width, height, a.out, gi.get());
  if (!run.stats.empty()) {
    std::printf("\n");
    for (const auto& [k, v] : run.stats) std::printf("%-20s%14.6g\n", k.c_str(), v);
  }
  if (run.has_counts) std::printf("%-20s%14zu\n", "memory bytes", run.counted.memory_bytes);
  if (!a.out.empty()) std::printf("\nwrote %s\n", a.out.c_str());
  for (const std::string* file : {&a.heatmap, &a.ratio_map})
    if (!file->empty()) std::printf("wrote %s\n", file->c_str());
  writeLightsGltf(a.inputs.write_lights, inputs.lights);
  if (!a.inputs.write_lights.empty())
    std::printf("wrote %s (%zu lights)\n", a.inputs.write_lights.c_str(), inputs.lights.size());
  if (!a.stats_json.empty()) writeStatsJson(a, tech, inputs, run, ctx, width, height);
  return 0;
}

}  // namespace ml
