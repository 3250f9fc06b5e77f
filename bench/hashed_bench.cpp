// manylights-hashed-bench: hashed shading's build (time per stage, memory,
// table sizes) against node size and light count, light evaluations per
// shaded pixel against tiled and clustered shading and the exact lower bound
// in the same run, incremental updates (1%, 10%, 100% of the lights moving)
// against full rebuilds, and the thesis suite's 1890-light Spaceship set
// when the thesis suite is present (skipped, visibly, when not): --suite, else
// $MANYLIGHTS_THESIS_SUITE/scenes/spaceship-indoor, else
// ../shared/data/thesis-suite/scenes/spaceship-indoor next to the checkout.
// Prints tables; --json writes every record. The build and update sections
// are host-side (no GL/CL); section 4 renders through the run layer.
#include "ml_build_paths.h"  // MANYLIGHTS_SOURCE_DIR (generated)
#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <thread>

#include "HashedBuildStats.hpp"
#include "host/run/SceneInputs.hpp"
#include "host/run/OutputFiles.hpp"
#include "host/scene/LightAnimator.hpp"
#include "host/techniques/Registry.hpp"
#include "BenchCommon.hpp"
#include "BenchSupport.hpp"

namespace {
using namespace ml;
using benchutil::median;
using json = nlohmann::ordered_json;
using LightSets = std::vector<std::pair<std::string, std::vector<gpu::PointLight>>>;

// The thesis suite's Spaceship Indoor scene (benchutil::thesisSuiteScene).
std::string defaultSuiteScene() { return benchutil::thesisSuiteScene("spaceship-indoor"); }

struct Args {
  benchutil::BenchArgs common;
  std::string light_counts = "1024,4096", node_sizes = "0.25r,0.5r,1r,2r", size = "640x360";
  std::string suite_dir = defaultSuiteScene();
  // "tiled-deferred@32/none": the thesis's tiled baseline (32x32 tiles, no depth bounds).
  std::string compare = "tiled-deferred,tiled-deferred@32/none,clustered-deferred";
  std::string update_fractions = "0.01,0.1,1";
  int update_reps = 5;
  unsigned camera_frames = 4;
  bool no_render = false, no_octant_masks = false, update_geometry_mask = false, scale = false;
};

// --- 1. Build time, memory, table sizes vs node size and light count ---
json buildSection(const Args& a, const SceneInputs& base, const LightSets& light_sets) {
  std::printf("\n1. Build (default scene, generated lights; median of %d; times in ms; +g: geometry mask; "
              "-o: no octant masks)\n", a.common.reps);
  printBuildHeader();
  json builds = json::array();
  for (const auto& [label, lights] : light_sets)
    for (const auto& node : splitList(a.node_sizes)) {
      hashed::HashedConfig cfg;
      cfg.node_size = node;
      const BuildRecord r = timedBuild(lights, cfg, nullptr, a.common.reps);
      printBuild(label, node, r);
      cfg.octant_masks = false;
      const BuildRecord o = timedBuild(lights, cfg, nullptr, a.common.reps);
      printBuild(label, node + "-o", o);
      cfg.octant_masks = true;
      cfg.geometry_mask = true;
      const BuildRecord m = timedBuild(lights, cfg, &base.scene, a.common.reps);
      printBuild(label, node + "+g", m);
      builds.push_back({{"lights", lights.size()}, {"node_size", node}, {"plain", buildJson(r)},
                        {"no_octant_masks", buildJson(o)}, {"geometry_mask", buildJson(m)},
                        {"geometry_mask_memory_ratio", double(m.gpu_bytes) / double(r.gpu_bytes)},
                        {"octant_masks_memory_ratio", double(r.gpu_bytes) / double(o.gpu_bytes)}});
    }
  return builds;
}

// Per-update samples of one light set and moving fraction.
struct UpdateSamples {
  std::vector<double> total, oct, tree, sync, cpu, rebuild_ms, rebuild_cpu;
  std::size_t rehashed = 0, reoffset = 0, full = 0, moved = 0;
};

// `reps` updates with the same motion as --animate (distinct lights, steps of
// up to r/4, staying within r/2 of their start), each followed by a full build
// of the same lights, so that both see the same machine (its speed here drifts
// by up to a third within seconds) and the same cold caches.
UpdateSamples measureUpdates(const std::vector<gpu::PointLight>& lights0, const hashed::HashedConfig& cfg,
                             const Scene* scene, double fraction, int reps) {
  UpdateSamples s;
  LightAnimator anim(lights0, fraction);
  s.moved = anim.movesPerStep();
  hashed::HashedStructure hs(cfg, scene);
  hs.build(lights0);
  for (int i = 0; i < reps; ++i) {
    const auto& lights = anim.step();
    const double c0 = benchutil::cpuSeconds();
    const auto& st = hs.update(lights);
    s.cpu.push_back((benchutil::cpuSeconds() - c0) * 1e3);
    {
      hashed::HashedStructure fresh(cfg, scene);
      const double r0 = benchutil::cpuSeconds();
      fresh.build(lights);
      s.rebuild_cpu.push_back((benchutil::cpuSeconds() - r0) * 1e3);
      s.rebuild_ms.push_back(fresh.lastBuild().total_ms);
    }
    s.full += st.full_rebuild;
    s.total.push_back(st.total_ms);
    s.oct.push_back(st.light_octrees_ms);
    s.tree.push_back(st.tree_ms);
    s.sync.push_back(st.sync_ms);
    s.rehashed += st.sync.rehashed_tables;
    s.reoffset += st.sync.reoffsets;
  }
  return s;
}

// The row and the record of one update case (medians; min ratio: fastest update / fastest rebuild).
json reportUpdates(const std::string& label, std::size_t lights, double fraction, int reps, const UpdateSamples& s) {
  const double rebuild = median(s.rebuild_ms), rebuild_c = median(s.rebuild_cpu);
  const double rebuild_min = *std::min_element(s.rebuild_ms.begin(), s.rebuild_ms.end());
  const double upd = median(s.total), upd_c = median(s.cpu);
  const double upd_min = *std::min_element(s.total.begin(), s.total.end());
  std::printf("%-9s %6.0f%% %10.2f %10.2f %7.1f%% %8.1f%% %8.1f%% %8.2f %8.2f %8.2f %9zu %9zu%s\n", label.c_str(),
              fraction * 100, upd, rebuild, 100.0 * upd / rebuild, 100.0 * upd_c / rebuild_c,
              100.0 * upd_min / rebuild_min, median(s.oct), median(s.tree), median(s.sync), s.rehashed, s.reoffset,
              s.full ? "  (some left the bounds: rebuilt)" : "");
  return {{"lights", lights}, {"fraction", fraction}, {"moved_per_update", s.moved}, {"update_ms", upd},
          {"rebuild_ms", rebuild}, {"ratio", upd / rebuild}, {"update_min_ms", upd_min},
          {"rebuild_min_ms", rebuild_min}, {"min_ratio", upd_min / rebuild_min}, {"update_cpu_ms", upd_c},
          {"rebuild_cpu_ms", rebuild_c}, {"cpu_ratio", upd_c / rebuild_c}, {"light_octrees_ms", median(s.oct)},
          {"tree_ms", median(s.tree)}, {"sync_ms", median(s.sync)}, {"rehashed_tables", s.rehashed},
          {"reoffset_groups", s.reoffset}, {"full_rebuilds", s.full}, {"updates", reps}};
}

// --- 2. Incremental updates vs full rebuild ---
json updateSection(const Args& a, const Scene& base, const LightSets& update_sets) {
  std::printf("\n2. Updates (0.5r%s; lights move up to r/4; median of %d; ms; each update followed by a full build "
              "of the same lights (rebuild); min ratio: fastest update / fastest rebuild)\n",
              a.update_geometry_mask ? ", geometry mask" : "", a.update_reps);
  std::printf("%-9s %7s %10s %10s %8s %9s %9s %8s %8s %8s %9s %9s\n", "lights", "moving", "update", "rebuild", "ratio",
              "cpu ratio", "min ratio", "octrees", "tree", "sync", "rehashed", "re-offset");
  json updates = json::array();
  for (const auto& [label, lights0] : update_sets) {
    // The mask is the default scene's: the suite's lights belong to another scene.
    if (a.update_geometry_mask && label == "suite1890") continue;
    hashed::HashedConfig cfg;
    cfg.node_size = "0.5r";
    cfg.max_incremental_fraction = 1.0;  // measure the incremental path itself
    cfg.octant_masks = !a.no_octant_masks;
    cfg.geometry_mask = a.update_geometry_mask;
    for (const auto& fraction_text : splitList(a.update_fractions)) {
      const double fraction = std::stod(fraction_text);
      const UpdateSamples s = measureUpdates(lights0, cfg, a.update_geometry_mask ? &base : nullptr, fraction, a.update_reps);
      updates.push_back(reportUpdates(label, lights0.size(), fraction, a.update_reps, s));
    }
  }
  return updates;
}

// --- S. At scale (--scale): the renderer's defaults (geometry mask, octant
// masks) with the memory limit lifted, so that a case over the limit is
// measured rather than refused: stages, peak resident bytes against the
// estimate the limit checks, and 1% of the lights moving against a rebuild.
json scaleSection(const Args& a, const SceneInputs& base, const LightSets& light_sets) {
  std::printf("\nS. At scale (geometry mask; median of %d; ms; peak: resident bytes the build added)\n", a.common.reps);
  printBuildHeader();
  json out = json::array();
  for (const auto& [label, lights] : light_sets)
    for (const auto& node : splitList(a.node_sizes)) {
      hashed::HashedConfig cfg;
      cfg.node_size = node;
      cfg.geometry_mask = true;
      cfg.memory_limit = std::size_t(-1);
      const BuildRecord r = timedBuild(lights, cfg, &base.scene, a.common.reps);
      printBuild(label, node + "+g", r);
      const double n = double(std::max<std::size_t>(1, lights.size()));
      std::printf("   mask %.1f ms (%zu cells), bounds %.1f ms; lit cells %.1f per light; peak %.0f B/light, "
                  "estimate %.0f B/light\n", r.stats.mask_ms, r.stats.mask_cells, r.stats.bounds_ms,
                  double(r.stats.filled_cells) / n, double(r.peak_bytes) / n, double(r.estimated_bytes) / n);
      // What the renderer's checks (1 GiB by default) make of this case: the
      // octree estimate before the build, the mask's own count during it.
      const double mask_peak = double(r.stats.mask_bytes);
      const bool fits = double(r.estimated_bytes) <= double(hashed::HashedConfig{}.memory_limit) &&
                        mask_peak <= double(hashed::HashedConfig{}.memory_limit);
      std::printf("   geometry mask peak %.0f MiB; within the default limit: %s\n", mib(mask_peak),
                  fits ? "yes" : "no");
      json rec = {{"lights", lights.size()}, {"node_size", node}, {"build", buildJson(r)},
                  {"mask_peak_bytes", mask_peak}, {"fits_default_limit", fits}};
      for (const auto& fraction_text : splitList(a.update_fractions)) {
        const double fraction = std::stod(fraction_text);
        const UpdateSamples s = measureUpdates(lights, cfg, &base.scene, fraction, a.update_reps);
        rec["updates"].push_back(reportUpdates(label, lights.size(), fraction, a.update_reps, s));
      }
      out.push_back(rec);
    }
  return out;
}

// --- 3. Thesis suite: the 1890-light Spaceship Indoor set ---
json suiteSection(const Args& a, const std::string& suite_lights) {
  std::printf("\n3. Thesis suite: Spaceship Indoor, 1890 lights\n");
  if (!std::filesystem::exists(suite_lights)) {
    std::printf("   SKIPPED: %s not found (the project does not ship the thesis suite)\n",
                reportPath(suite_lights).c_str());
    return {{"skipped", "missing " + reportPath(suite_lights)}};
  }
  const auto lights = loadLightsJson(suite_lights);
  printBuildHeader();
  json suite = json::array();
  for (const auto& node : {"0.25r", "0.5r", "1r"}) {
    hashed::HashedConfig cfg;
    cfg.node_size = node;
    const BuildRecord r = timedBuild(lights, cfg, nullptr, std::max(a.common.reps, 5));
    printBuild(std::to_string(lights.size()), node, r);
    suite.push_back({{"lights", lights.size()}, {"node_size", node}, {"build", buildJson(r)}});
  }
  return suite;
}

using Given = std::vector<std::pair<std::string, std::string>>;  // technique parameters, by key

// The runs of section 4: --compare ("name@tile/depth" sets tile and tile_depth),
// then hashed per node size, with and without the geometry mask and octant masks.
std::vector<std::pair<std::string, Given>> evalRuns(const Args& a) {
  std::vector<std::pair<std::string, Given>> runs;
  for (const auto& t : splitList(a.compare)) {
    Given p;
    if (const auto at = t.find('@'); at != std::string::npos) {
      const auto slash = t.find('/', at);
      p.emplace_back("tile", t.substr(at + 1, slash - at - 1));
      if (slash != std::string::npos) p.emplace_back("tile_depth", t.substr(slash + 1));
    }
    runs.emplace_back(t, p);
  }
  for (const auto& node : splitList(a.node_sizes))
    for (const bool mask : {false, true})
      for (const bool octants : {true, false})
        runs.emplace_back("hashed-deferred " + node + (mask ? "+g" : "") + (octants ? "" : "-o"),
                          Given{{"node_size", node}, {"geometry_mask", mask ? "on" : "off"},
                                {"octant_masks", octants ? "on" : "off"}});
  return runs;
}

// Counted deferred frames of `cams` with one run's assigner, summed: a row and
// a record (skipped, with a row saying why, when the registry refuses it).
void countRun(benchutil::BenchSetup& b, FrameRenderer& r, const std::vector<const Camera*>& cams,
              const std::string& label, std::size_t n, const std::pair<std::string, Given>& run, double& tiled_px,
              json& evals) {
  const auto& [name, params] = run;
  const std::string tech = name.substr(0, std::min(name.find(' '), name.find('@')));
  std::unique_ptr<LightAssigner> a;
  try {
    const TechniqueInfo& info = findTechnique(tech, "--compare");
    a = makeAssigner(info, b.cl(), techniqueParams(info, params, "--compare"), &b.scene.scene);
  } catch (const UserError& e) {
    std::printf("%-8s %-24s skipped: %s\n", label.c_str(), name.c_str(), e.what());
    return;
  }
  std::uint64_t ev = 0, lb = 0, px = 0;
  std::size_t mem = 0;
  for (const Camera* c : cams) {
    const FrameResult fr = countedRender(r, *a, {Pipeline::Deferred}, *c);
    ev += fr.light_evaluations;
    lb += fr.lower_bound;
    px += fr.covered_pixels;
    mem = std::max(mem, fr.memory_bytes);
  }
  const double per_px = double(ev) / double(px), bound_px = double(lb) / double(px);
  if (name == "tiled-deferred") tiled_px = per_px;
  std::printf("%-8s %-24s %12.2f %12.2f %10.3f %10s %12.3f\n", label.c_str(), name.c_str(), per_px, bound_px,
              per_px / bound_px, tiled_px > 0 ? std::to_string(per_px / tiled_px).substr(0, 6).c_str() : "-",
              mib(double(mem)));
  evals.push_back({{"lights", n}, {"technique", name}, {"evaluations_per_pixel", per_px},
                   {"lower_bound_per_pixel", bound_px}, {"ratio_to_bound", per_px / bound_px},
                   {"ratio_to_tiled", tiled_px > 0 ? per_px / tiled_px : 0.0}, {"memory_bytes", mem},
                   {"covered_pixels", px}});
}

// --- 4. Light evaluations per shaded pixel (same run: tiled, clustered) ---
json evalSection(const Args& a, const SceneInputs& base, const LightSets& light_sets) {
  const auto [width, height] = benchutil::sizeOf(a.size, "--size");
  std::printf("\n4. Light evaluations per covered pixel, deferred, %ux%u, %u camera frames; +g: geometry mask, -o: no "
              "octant masks\n", width, height, a.camera_frames);
  benchutil::BenchSetup b = benchutil::BenchSetup::open(a.common.device, base);
  std::printf("%-8s %-24s %12s %12s %10s %10s %12s\n", "lights", "technique", "evals/px", "bound/px", "x bound",
              "x tiled", "memory MiB");
  FrameRenderer r(b.cl(), b.scene.scene, width, height);
  const auto& path = b.scene.cameras.frames;
  std::vector<const Camera*> cams;
  for (unsigned i = 0; i < a.camera_frames; ++i)
    cams.push_back(&path[std::size_t(i) * path.size() / std::max(1u, a.camera_frames)]);
  json evals = json::array();
  for (const auto& [label, lights] : light_sets) {
    r.setLights(lights);
    double tiled_px = 0;
    for (const auto& run : evalRuns(a)) countRun(b, r, cams, label, lights.size(), run, tiled_px, evals);
  }
  return evals;
}

void parseArgs(CLI::App& app, Args& a) {
  a.common.reps = 3;
  benchutil::addBenchArgs(app, a.common, "builds per case (median reported)");
  app.add_option("--lights", a.light_counts, "generated light counts in the default scene")->capture_default_str();
  app.add_option("--node-sizes", a.node_sizes, "node sizes to sweep")->capture_default_str();
  app.add_option("--size", a.size, "render resolution for light evaluations")->capture_default_str();
  app.add_option("--camera-frames", a.camera_frames, "camera path frames averaged")->capture_default_str();
  app.add_option("--compare", a.compare, "techniques counted in the same run ('' for none)")->capture_default_str();
  app.add_option("--update-reps", a.update_reps, "updates per case (median reported)")->capture_default_str();
  app.add_option("--update-fractions", a.update_fractions, "fractions of the lights moving per update")
      ->capture_default_str();
  // The default is a path on this machine: described, not printed.
  app.add_option("--suite", a.suite_dir,
                 "thesis suite scene folder (its lights/ holds the 1890-light set); default: "
                 "$MANYLIGHTS_THESIS_SUITE/scenes/spaceship-indoor, else ../shared/data/thesis-suite/... "
                 "beside the source tree");
  app.add_flag("--no-render", a.no_render, "host-side sections only");
  app.add_flag("--scale", a.scale,
               "only: builds with the geometry mask (memory limit lifted, peak resident bytes) and updates of "
               "--update-fractions, per --lights and --node-sizes");
  app.add_flag("--no-octant-masks", a.no_octant_masks,
               "updates: the thesis's plain light lists (HashedConfig::octant_masks off)");
  app.add_flag("--update-geometry-mask", a.update_geometry_mask,
               "updates: with the default scene's geometry mask (the renderer's default; generated light sets only)");
}

int run(int argc, char** argv) {
  CLI::App app{"Hashed shading: build, memory, light evaluations and dynamic updates"};
  Args a;
  parseArgs(app, a);
  if (const auto stop = benchutil::parseCommandLine(app, argc, argv, a.common,
                                                    [&] { (void)benchutil::sizeOf(a.size, "--size"); }))
    return *stop;

  json out;
  out["tool"] = "manylights-hashed-bench";
  out["cpu_threads"] = std::thread::hardware_concurrency();
  const SceneInputs base = benchutil::defaultScene();
  LightSets light_sets;
  for (const auto& c : splitList(a.light_counts))
    light_sets.emplace_back(c, benchutil::generatedLights(c, a.common.light_density));
  if (a.scale) {
    out["scale"] = scaleSection(a, base, light_sets);
    benchutil::writeJson(a.common.json_path, out);
    return 0;
  }
  out["builds"] = buildSection(a, base, light_sets);

  const std::string suite_lights = a.suite_dir + "/lights/1890#3x_3y_3z.json";
  LightSets update_sets = light_sets;
  if (std::filesystem::exists(suite_lights)) update_sets.emplace_back("suite1890", loadLightsJson(suite_lights));
  out["updates"] = updateSection(a, base.scene, update_sets);
  out["updates_octant_masks"] = !a.no_octant_masks;
  if (a.update_geometry_mask) out["updates_geometry_mask"] = true;
  out["thesis_suite"] = suiteSection(a, suite_lights);
  if (!a.no_render) out["light_evaluations"] = evalSection(a, base, light_sets);
  benchutil::writeJson(a.common.json_path, out);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  return ml::benchutil::benchMain("manylights-hashed-bench", [&] { return run(argc, argv); });
}
