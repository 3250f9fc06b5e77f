#include "host/app/RenderCommand.hpp"

#include <nlohmann/json.hpp>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <charconv>
#include <cstdio>
#include <random>

#include "gl/FrameRenderer.hpp"
#include "gl/GlContext.hpp"
#include "host/app/InputChecks.hpp"
#include "host/bench/OutputFiles.hpp"
#include "host/cl/ClRuntime.hpp"
#include "host/cl/KernelLimits.hpp"
#include "host/hashed/HashedAssigner.hpp"
#include "host/scene/LightAnimator.hpp"
#include "host/clustered/ClusteredAssigner.hpp"
#include "host/util/Error.hpp"
#include "host/util/Heatmap.hpp"
#include "host/util/ImageIO.hpp"

namespace ml {

void parseSize(const std::string& text, const std::string& flag, unsigned& w, unsigned& h) {
  const auto x = text.find('x');
  auto num = [&](std::string_view s, unsigned& v) {
    auto [p, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
    return ec == std::errc() && p == s.data() + s.size();
  };
  if (x == std::string::npos || !num(std::string_view(text).substr(0, x), w) ||
      !num(std::string_view(text).substr(x + 1), h) || w == 0 || h == 0 || w > 16384 || h > 16384)
    throw UserError(flag + ": expected WIDTHxHEIGHT with 1..16384 pixels each, got '" + text + "'");
}

void addSceneInputFlags(CLI::App& cmd, SceneInputArgs& a) {
  cmd.add_option("--scene", a.scene, "glTF scene (.gltf/.glb); default: data/default/scene.glb");
  cmd.add_option("--lights", a.lights,
                 "light count to generate (in the scene's light volumes) or a light JSON file; "
                 "default: data/default/lights.json");
  cmd.add_option("--camera", a.camera, "camera or camera-path JSON; default: data/default/camera.json");
  cmd.add_option("--light-volumes", a.light_volumes, "JSON boxes that generated lights are placed in");
  cmd.add_option("--light-radius", a.light_radius, "radius of generated lights (default: from the volume file)")
      ->check(finitePositive());
  cmd.add_option("--seed", a.seed, "seed for generated lights (default 23, the thesis's)");
}

namespace {
// --cluster-view target; kept here rather than in RenderArgs so the clustered
// technique touches only this file of the render command.
std::string g_cluster_view;
}  // namespace

namespace {
// --animate F: before every timed frame a fraction F of the lights (distinct,
// chosen at random, seed 23) takes a random step (LightAnimator). Kept here so
// the option touches only this file.
double g_animate = 0.0;
double g_animate_speed = 0.25;
}  // namespace

CLI::App* addRenderCommand(CLI::App& app, RenderArgs& a) {
  auto* cmd = app.add_subcommand("render", "Render one frame with one technique; print per-pass times and counts");
  addSceneInputFlags(*cmd, a.inputs);
  cmd->add_option("--technique", a.technique, "one of: " + techniqueNames())->capture_default_str();
  cmd->add_option("--size", a.size, "WIDTHxHEIGHT")->capture_default_str();
  cmd->add_option("--frame", a.frame, "index into the camera path")->capture_default_str();
  cmd->add_option("--frames", a.frames, "timed frames (median reported)")->capture_default_str();
  cmd->add_option("--warmup", a.warmup, "untimed frames first")->capture_default_str();
  cmd->add_option("--out", a.out, "output image (.png 8-bit, .exr float; other extensions are refused)");
  cmd->add_option("--device", a.device, "OpenCL device: gpu, cpu or an index from `manylights devices`");
  cmd->add_option("--heatmap", a.heatmap, "write a heat map of lights evaluated per pixel (cubehelix) to this PNG");
  cmd->add_option("--heatmap-max", a.heatmap_max, "count mapped to the top of the palette (default: frame max)");
  cmd->add_flag("--counts", a.counts, "count light evaluations and the exact lower bound (extra frame)");
  cmd->add_option("--stats-json", a.stats_json, "write times and counts as JSON (implies --counts)");
  cmd->add_option("--tile", a.params.tile_size, "tile size in pixels (tiled techniques)")->capture_default_str();
  cmd->add_option("--tile-depth", a.params.tile_depth, "tiled depth culling: none|minmax|mask")->capture_default_str();
  cmd->add_option("--cluster-tile", a.params.cluster_tile,
                  "cluster tile size in pixels; 0: auto (32 from 720 lines up, as in the thesis; 16 below)")
      ->capture_default_str();
  cmd->add_option("--unique", a.params.unique_method, "unique clusters: pagetable|sort|tile-sort")
      ->capture_default_str();
  cmd->add_option("--cluster-assign", a.params.cluster_assign, "cluster light assignment: bvh|brute")
      ->capture_default_str();
  cmd->add_option("--cluster-bounds", a.params.cluster_bounds,
                  "clustered: cull against the AABB of each cluster's pixels or of its sub-frustum: pixels|frustum")
      ->capture_default_str();
  cmd->add_option("--kernel-shape", a.params.kernel_shape,
                  "OpenCL kernel shape of tiled and clustered shading: auto (by device type)|cpu|gpu")
      ->capture_default_str();
  cmd->add_option("--cluster-view", g_cluster_view, "clustered: write each unique cluster as a colour to this PNG");
  cmd->add_option("--node-size", a.params.node_size, "hashed: minimal node size, absolute or relative (0.5r)")
      ->capture_default_str();
  cmd->add_option("--start-depth", a.params.start_depth, "hashed: octree start depth")->capture_default_str();
  cmd->add_flag("--geometry-mask", a.params.geometry_mask, "hashed: keep only nodes that contain geometry");
  cmd->add_flag("--octant-masks,!--no-octant-masks", a.params.octant_masks,
                "hashed: skip lights that miss the point's octant of its deepest cell (default on)");
  cmd->add_option("--animate", g_animate,
                  "move this fraction of the lights (0..1) before every timed frame (hashed: incremental update)");
  cmd->add_option("--animate-speed", g_animate_speed,
                  "--animate step per axis, times the light radius (lights stay within twice that of their start)")
      ->capture_default_str();
  return cmd;
}

namespace {
// Flags checked before any input is loaded (InputChecks.hpp): technique
// parameters, output paths (writable, image extensions), a generated light
// count against the technique's and the memory limits.
void checkRenderFlags(const RenderArgs& a, const TechniqueInfo& tech) {
  checkRenderTechniqueParams(a.params);
  if (!g_cluster_view.empty() && tech.name.find("clustered") == std::string::npos)
    throw UserError("--cluster-view: needs a clustered technique, got '" + tech.name + "'");
  requireImageFile("--out", a.out);
  requireImageFile("--heatmap", a.heatmap);
  requireImageFile("--cluster-view", g_cluster_view);
  requireOutputFile("--stats-json", a.stats_json);
  std::uint64_t count = 0;
  if (parseLightCount(a.inputs.lights, count)) checkLightLimits("--lights", count, {&tech}, "generated");
}
}  // namespace

int runRender(const RenderArgs& a) {
  unsigned width = 0, height = 0;
  parseSize(a.size, "--size", width, height);
  const TechniqueInfo& tech = findTechnique(a.technique);
  (void)parseKernelShape(a.params.kernel_shape);  // a bad --kernel-shape fails before any GL/CL work
  if (a.frames == 0) throw UserError("--frames: must be at least 1");
  // Validates --animate and --animate-speed before any GL/CL work.
  (void)LightAnimator({}, g_animate, 23, g_animate_speed);
  checkRenderFlags(a, tech);
  const DeviceChoice device = DeviceChoice::resolve(a.device);

  SceneInputs inputs = loadSceneInputs(a.inputs);
  if (a.frame >= inputs.cameras.frames.size())
    throw UserError("--frame: " + std::to_string(a.frame) + " is past the camera path's " +
                    std::to_string(inputs.cameras.frames.size()) + " frames");
  checkLightLimits("--lights", inputs.lights.size(), {&tech}, a.inputs.lights.empty() ? "default" : a.inputs.lights);

  auto gl = createHeadlessContext();
  const GlShareHandles share = gl->shareHandles();
  auto cl = ClRuntime::create(device, &share);
  checkDeviceLightLimits("--lights", inputs.lights.size(), cl->info());
  std::printf("%s\n%s\n", cl->describe().c_str(), gl->describe().c_str());
  std::printf("scene: %s (%zu triangles) | lights: %s | %ux%u | technique: %s\n", reportPath(inputs.scene.source).c_str(),
              inputs.scene.triangleCount(), inputs.lights_label.c_str(), width, height, tech.name.c_str());

  FrameRenderer renderer(*cl, inputs.scene, width, height);
  renderer.setLights(inputs.lights);
  auto assigner = makeAssigner(tech.name, *cl, a.params);
  attachSceneGeometry(*assigner, inputs.scene);
  const Camera& camera = inputs.cameras.frames[a.frame];
  FrameOptions opts;
  opts.pipeline = tech.pipeline;

  for (unsigned i = 0; i < a.warmup; ++i) renderer.render(camera, *assigner, opts);
  std::vector<FrameResult> timed;
  LightAnimator animator(inputs.lights, g_animate, 23, g_animate_speed);
  if (g_animate > 0.0)
    std::printf("animate: %zu of %zu lights move before each timed frame (step %g r)\n", animator.movesPerStep(),
                inputs.lights.size(), g_animate_speed);
  for (unsigned i = 0; i < a.frames; ++i) {
    if (animator.movesPerStep() > 0) renderer.setLights(animator.step());
    timed.push_back(renderer.render(camera, *assigner, opts));
  }
  if (!a.out.empty())
    writeImageAtomically("--out", a.out, width, height, 4, renderer.targets().readColor());

  // Median per pass over the timed frames.
  auto median = [](std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v.empty() ? 0.0 : v[v.size() / 2];
  };
  PassTimings med;
  for (const auto& [name, ms] : timed.front().passes.entries()) {
    (void)ms;
    std::vector<double> v;
    for (const auto& f : timed) v.push_back(f.passes.get(name));
    med.add(name, median(v));
  }
  std::vector<double> host;
  for (const auto& f : timed) host.push_back(f.host_ms);
  const double host_ms = median(host);

  std::printf("\n%-24s %10s\n", "pass", "ms (median)");
  for (const auto& [name, ms] : med.entries()) std::printf("%-24s %10.3f\n", name.c_str(), ms);
  std::printf("%-24s %10.3f\n", "sum of passes", med.total());
  std::printf("%-24s %10.3f\n", "frame (host wall)", host_ms);

  FrameResult counted;
  const bool want_counts = a.counts || !a.stats_json.empty() || !a.heatmap.empty();
  if (want_counts) {
    FrameOptions copts = opts;
    copts.count_lights = true;
    counted = renderer.render(camera, *assigner, copts);
    if (!a.heatmap.empty()) {
      const auto depth = renderer.targets().readDepth(tech.pipeline == Pipeline::Deferred);
      std::vector<bool> covered(depth.size());
      for (size_t i = 0; i < depth.size(); ++i) covered[i] = !gpu::is_sky_depth(depth[i]);
      writeImageAtomically("--heatmap", a.heatmap, width, height, 4,
                           heatmapRgba(renderer.targets().readCounts(), 2, 0, covered, a.heatmap_max));
    }
    const double per_px = counted.covered_pixels ? double(counted.light_evaluations) / counted.covered_pixels : 0.0;
    const double lb_px = counted.covered_pixels ? double(counted.lower_bound) / counted.covered_pixels : 0.0;
    std::printf("\nlight evaluations   %14llu  (%.2f per covered pixel)\n",
                static_cast<unsigned long long>(counted.light_evaluations), per_px);
    std::printf("exact lower bound   %14llu  (%.2f per covered pixel)\n",
                static_cast<unsigned long long>(counted.lower_bound), lb_px);
    std::printf("missed lights       %14llu  (bound lights not evaluated: must be 0)\n",
                static_cast<unsigned long long>(counted.missed_lights));
    std::printf("ratio to bound      %14.3f\n",
                counted.lower_bound ? double(counted.light_evaluations) / counted.lower_bound : 0.0);
    std::printf("covered pixels      %14llu\n", static_cast<unsigned long long>(counted.covered_pixels));
    std::printf("fragment evaluations%14llu  (all shaded fragments, overdraw included)\n",
                static_cast<unsigned long long>(counted.fragment_evaluations));
  }
  if (!g_cluster_view.empty()) {
    auto* clustered = dynamic_cast<ClusteredAssigner*>(assigner.get());
    if (!clustered) throw UserError("--cluster-view needs a clustered technique");
    writeImageAtomically("--cluster-view", g_cluster_view, width, height, 4,
                         ClusteredAssigner::clusterViewRgba(clustered->readClusterMap()));
    std::printf("wrote %s\n", g_cluster_view.c_str());
  }
  const auto extra = assigner->stats();
  if (!extra.empty()) {
    std::printf("\n");
    for (const auto& [k, v] : extra) std::printf("%-20s%14.6g\n", k.c_str(), v);
  }
  if (want_counts) std::printf("%-20s%14zu\n", "memory bytes", counted.memory_bytes);
  if (!a.out.empty()) std::printf("\nwrote %s\n", a.out.c_str());
  if (!a.heatmap.empty()) std::printf("wrote %s\n", a.heatmap.c_str());

  if (!a.stats_json.empty()) {
    nlohmann::ordered_json j;
    j["technique"] = tech.name;
    j["width"] = width;
    j["height"] = height;
    j["lights"] = inputs.lights.size();
    j["frame"] = a.frame;
    j["timed_frames"] = a.frames;
    j["animate"] = g_animate;
    j["animated_lights_per_frame"] = animator.movesPerStep();
    nlohmann::ordered_json passes = nlohmann::ordered_json::object();
    for (const auto& [name, ms] : med.entries()) passes[name] = ms;
    j["passes"] = passes;
    j["frame_host_ms"] = host_ms;
    j["light_evaluations"] = counted.light_evaluations;
    j["lower_bound"] = counted.lower_bound;
    j["missed_lights"] = counted.missed_lights;
    j["covered_pixels"] = counted.covered_pixels;
    j["fragment_evaluations"] = counted.fragment_evaluations;
    j["memory_bytes"] = counted.memory_bytes;
    nlohmann::ordered_json st = nlohmann::ordered_json::object();
    for (const auto& [k, v] : extra) st[k] = v;
    j["technique_stats"] = st;
    j["device"] = cl->info().name;
    j["gl"] = gl->describe();
    writeFileAtomically("--stats-json", a.stats_json, j.dump(2) + "\n");
  }
  return 0;
}

}  // namespace ml
