#include "host/app/CompareReferenceCommand.hpp"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <map>
#include <memory>
#include <set>

#include "gl/FrameRenderer.hpp"
#include "host/app/InputFlags.hpp"
#include "host/run/SceneInputs.hpp"
#include "host/run/RunRecords.hpp"
#include "host/run/OutputFiles.hpp"
#include "host/run/Progress.hpp"
#include "host/bench/ReferenceComparison.hpp"
#include "host/run/RunLayer.hpp"
#include "host/scene/LightSet.hpp"
#include "host/suite/ThesisReference.hpp"
#include "host/techniques/Registry.hpp"
#include "host/util/Error.hpp"

namespace ml {
namespace fs = std::filesystem;
namespace {

// The command line's selection, checked before anything loads.
struct Selection {
  std::map<std::string, std::string> technique_of;  // "ns" | "ts" | "cs" -> our technique
  std::set<std::string> only_techniques;
  std::set<unsigned> only_tiles;
  FrameRange range;
  Progress::Mode progress = Progress::Mode::Auto;
  DeviceChoice device;
};

Selection parseSelection(const CompareReferenceArgs& a) {
  Selection sel;
  for (const auto& item : splitList(a.technique_map)) {
    const auto eq = item.find('=');
    const std::string kind = eq == std::string::npos ? "" : item.substr(0, eq);
    if (kind != "ns" && kind != "ts" && kind != "cs")
      throw UserError("--technique-map: expected ns=NAME,ts=NAME,cs=NAME, got '" + item + "'");
    sel.technique_of[kind] = item.substr(eq + 1);
  }
  for (const auto& t : splitList(a.techniques)) sel.only_techniques.insert(t);
  for (const auto& t : splitList(a.tiles)) {
    checkParam("tile", t, "--tiles");
    sel.only_tiles.insert(static_cast<unsigned>(std::stoul(t)));
  }
  checkParam("tile_depth", a.tile_depth, "--tile-depth");
  if (!(a.naive_scale > 0)) throw UserError("--naive-scale: must be positive");
  if (a.fovy != 0 && !(a.fovy > 0 && a.fovy < 180)) throw UserError("--fovy: must be in (0, 180) degrees");
  if (!a.frames.empty()) sel.range = parseFrameRange(a.frames, "--frames");
  sel.progress = Progress::parseMode(a.progress, "--progress");
  requireOutputFile("--json", a.json);
  requireOutputFile("--csv", a.csv);
  requireOutputFile("--markdown", a.markdown);
  sel.device = DeviceChoice::resolve(a.device);
  if (!fs::is_directory(a.suite)) throw UserError("--suite: '" + a.suite + "' is not a folder");
  return sel;
}

// Which series run with which technique and parameters (a bench variant each).
std::vector<SeriesRun> planSeries(const ThesisReference& ref, const Selection& sel, const CompareReferenceArgs& a) {
  std::vector<SeriesRun> runs;
  for (const auto& s : ref.series) {
    SeriesRun r;
    r.ref = &s;
    r.technique = sel.technique_of.count(s.kind) ? sel.technique_of.at(s.kind) : "";
    if (s.tile && !sel.only_tiles.empty() && !sel.only_tiles.count(s.tile)) continue;
    if (!sel.only_techniques.empty() && !sel.only_techniques.count(r.technique)) continue;
    const bool registered = std::any_of(techniques().begin(), techniques().end(),
                                        [&](const TechniqueInfo& t) { return t.name == r.technique; });
    if (r.technique.empty()) r.skipped = "no technique mapped";
    else if (!registered) r.skipped = "technique '" + r.technique + "' is not registered in this build";
    if (s.kind == "ts") r.param_labels = {{"tile", std::to_string(s.tile)}, {"tile_depth", a.tile_depth}};
    else if (s.kind == "cs") r.param_labels = {{"cluster_tile", std::to_string(s.tile)}};
    r.label = variantLabel(r.technique, r.param_labels);
    runs.push_back(std::move(r));
  }
  if (runs.empty()) throw UserError("--techniques/--tiles: nothing in the reference matches the selection");
  return runs;
}

// Each series' reference frames in --frames whose camera frame exists; the total.
std::size_t selectSeriesFrames(std::vector<SeriesRun>& runs, const FrameRange& range, int frame_offset,
                               std::size_t path_frames) {
  std::size_t total = 0;
  for (auto& r : runs) {
    if (!r.skipped.empty()) continue;
    for (const auto& entry : r.ref->counts) {
      const std::size_t f = entry.first;
      if (f < range.first || (range.last && f > *range.last) || (f - range.first) % range.step != 0) continue;
      const long cam = static_cast<long>(f) + frame_offset;
      if (cam < 0 || static_cast<std::size_t>(cam) >= path_frames) continue;
      r.frames.push_back(f);
    }
    if (r.frames.empty()) r.skipped = "no reference frame in --frames within the camera path";
    total += r.frames.size();
  }
  return total;
}

void printPlan(const ThesisReference& ref, const std::vector<SeriesRun>& runs, const RunScene& scene,
               const CompareReferenceArgs& a) {
  std::printf("thesis reference: %s (scene %s, %s)\n", ref.frames_dir.c_str(), ref.scene.c_str(), ref.pipeline.c_str());
  for (const auto& n : ref.notes) std::printf("note: %s\n", n.c_str());
  for (const auto& r : runs)
    if (!r.skipped.empty()) std::printf("note: skipped %s: %s\n", r.ref->id.c_str(), r.skipped.c_str());
  std::printf("scene: %s (%zu triangles, %zu camera frames)%s\n", scene.source.c_str(), scene.scene.triangleCount(),
              scene.cameras.frames.size(), scene.missing_meshes.empty() ? "" : ", with missing meshes skipped");
  std::printf("thesis naive counts x %g (NUM_LIGHTS x covered pixels / 10 as published); frame offset %d\n",
              a.naive_scale, a.frame_offset);
  std::fflush(stdout);
}

// Renders every selected frame of the runs, counted, through the run layer:
// one renderer per viewport, each light file loaded once.
class SeriesRenderer {
 public:
  SeriesRenderer(RunContext& ctx, const RunScene& scene, const CompareReferenceArgs& a, Progress& progress)
      : ctx_(ctx), scene_(scene), a_(a), progress_(progress) {}

  void run(SeriesRun& r) {
    const ReferenceSeries& s = *r.ref;
    const std::string light_path =
        s.light_file.empty() ? scene_.default_lights : (fs::path(a_.suite) / "lights" / s.light_file).string();
    if (!fs::is_regular_file(light_path)) {
      r.skipped = "its light set '" + s.light_file + "' is not in " + a_.suite + "/lights";
      r.frames.clear();
      std::printf("note: skipped %s: %s\n", s.id.c_str(), r.skipped.c_str());
      return;
    }
    if (!lights_.count(light_path)) lights_[light_path] = loadLightsJson(light_path);
    r.light_count = static_cast<std::uint32_t>(lights_[light_path].size());
    auto& renderer = renderers_[{s.width, s.height}];
    if (!renderer) renderer = std::make_unique<FrameRenderer>(*ctx_.cl, scene_.scene, s.width, s.height);
    renderer->setLights(lights_[light_path]);
    const TechniqueInfo& tech = findTechnique(r.technique, "--technique-map");
    auto assigner = makeAssigner(tech, *ctx_.cl, techniqueParams(tech, r.param_labels, "--technique-map"), &scene_.scene);
    for (std::size_t f : r.frames) {
      progress_.update(done_, s.id + " " + r.label + " frame " + std::to_string(f));
      const FrameResult res = countedRender(*renderer, *assigner, {.pipeline = tech.pipeline}, cameraOf(s, f));
      const double raw = s.counts.at(f);
      r.ours.push_back(static_cast<double>(res.light_evaluations));
      r.thesis_raw.push_back(raw);
      r.thesis.push_back(s.kind == "ns" ? raw * a_.naive_scale : raw);
      r.bound.push_back(static_cast<double>(res.lower_bound));
      r.covered.push_back(static_cast<double>(res.covered_pixels));
      ++done_;
    }
  }

 private:
  Camera cameraOf(const ReferenceSeries& s, std::size_t frame) const {
    Camera cam = scene_.cameras.frames[static_cast<std::size_t>(static_cast<long>(frame) + a_.frame_offset)];
    cam.fovy_degrees = a_.fovy > 0 ? a_.fovy : s.fovy;
    cam.near_plane = s.near_plane;
    cam.far_plane = s.far_plane;
    return cam;
  }

  RunContext& ctx_;
  const RunScene& scene_;
  const CompareReferenceArgs& a_;
  Progress& progress_;
  std::size_t done_ = 0;
  std::map<std::pair<unsigned, unsigned>, std::unique_ptr<FrameRenderer>> renderers_;
  std::map<std::string, std::vector<gpu::PointLight>> lights_;
};

}  // namespace

CLI::App* addCompareReferenceCommand(CLI::App& app, CompareReferenceArgs& a) {
  auto* cmd = app.add_subcommand(
      "compare-reference",
      "Compare our per-frame light evaluations with the thesis's published counts (lc_data.json): per technique and "
      "tile size, ours vs theirs, and the technique ratios side by side");
  cmd->footer(
      "Example:\n"
      "  manylights compare-reference --reference ../shared/data/thesis-suite/reference \\\n"
      "      --suite ../shared/data/thesis-suite/scenes/spaceship-indoor --allow-missing-meshes --frames 3:518:8\n"
      "The thesis's naive (ns) counts are NUM_LIGHTS x covered pixels / 10 (its resolution/ns-old data is exactly\n"
      "10x ns); they are compared after multiplying by --naive-scale. Tiled/clustered counts are compared as published.");
  cmd->add_option("--reference", a.reference, "the thesis's reference data (thesis-suite root, reference/ or "
                                               "reference/light_calculations/)")
      ->required();
  cmd->add_option("--suite", a.suite, "the scene-suite folder the reference was measured on")->required();
  cmd->add_option("--scene-name", a.scene_name, "scene folder name in the reference (default: the suite folder's)");
  cmd->add_option("--techniques", a.techniques, "only these of our techniques (default: every mapped one)");
  cmd->add_option("--tiles", a.tiles, "only these tile sizes, comma list (default: all in the reference)");
  cmd->add_option("--frames", a.frames, "FIRST:LAST:STEP over the reference's frame numbers (default: all)");
  cmd->add_option("--technique-map", a.technique_map, "series -> our technique")->capture_default_str();
  cmd->add_option("--tile-depth", a.tile_depth, "depth culling of our tiled technique (thesis: none)")
      ->capture_default_str();
  cmd->add_option("--naive-scale", a.naive_scale, "multiply the thesis's naive counts by this")->capture_default_str();
  cmd->add_option("--frame-offset", a.frame_offset, "our camera frame = reference frame + offset")
      ->capture_default_str();
  cmd->add_option("--coverage-tolerance", a.coverage_tolerance,
                  "frames whose covered pixels are within this fraction of the thesis's are also reported apart")
      ->capture_default_str();
  cmd->add_option("--fovy", a.fovy, "vertical field of view in degrees (default: the reference config's)");
  cmd->add_option("--json", a.json, "write per-frame values and summaries as JSON");
  cmd->add_option("--csv", a.csv, "write per-frame values as CSV");
  cmd->add_option("--markdown", a.markdown, "write the two tables as Markdown");
  addInputFlags(*cmd, {kSuiteFlags | kDeviceFlag | kProgressFlag, &a.inputs, &a.device, &a.progress});
  return cmd;
}

int runCompareReference(const CompareReferenceArgs& a) {
  const Selection sel = parseSelection(a);
  const std::string scene_name =
      a.scene_name.empty() ? fs::path(a.suite).lexically_normal().filename().string() : a.scene_name;
  const ThesisReference ref = loadThesisReference(a.reference, scene_name);
  std::vector<SeriesRun> runs = planSeries(ref, sel, a);

  SceneInputArgs sa = a.inputs;
  sa.scene = a.suite;
  const RunScene scene = loadRunScene(sa, "--suite");
  const std::size_t total_steps = selectSeriesFrames(runs, sel.range, a.frame_offset, scene.cameras.frames.size());
  printPlan(ref, runs, scene, a);

  if (total_steps > 0) {
    RunContext ctx = RunContext::open(sel.device);
    ctx.printDevices();
    std::fflush(stdout);
    Progress progress(total_steps, sel.progress);
    SeriesRenderer renderer(ctx, scene, a, progress);
    for (auto& r : runs)
      if (r.skipped.empty()) renderer.run(r);
    progress.finish();
  }
  const ComparisonSettings settings{a.naive_scale, a.coverage_tolerance, a.frame_offset, a.fovy, a.suite,
                                    scene.missing_meshes};
  reportComparison(ref, runs, settings, {a.json, a.csv, a.markdown});
  return 0;
}

}  // namespace ml
