// manylights-hashed-bench: hashed shading's build (time per stage, memory,
// table sizes) against node size and light count, light evaluations per
// shaded pixel against tiled and clustered shading and the exact lower bound
// in the same run, incremental updates (1%, 10%, 100% of the lights moving)
// against full rebuilds, and the thesis suite's 1890-light Spaceship set
// when the thesis suite is present (skipped, visibly, when not): --suite, else
// $MANYLIGHTS_THESIS_SUITE/scenes/spaceship-indoor, else
// ../shared/data/thesis-suite/scenes/spaceship-indoor next to the checkout.
// Prints tables; --json writes every record.
#include "ml_build_paths.h"  // MANYLIGHTS_SOURCE_DIR (generated)
#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <ctime>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <random>
#include <thread>

#include "gl/FrameRenderer.hpp"
#include "gl/GlContext.hpp"
#include "host/app/InputChecks.hpp"
#include "host/app/RenderCommand.hpp"
#include "host/app/SceneInputs.hpp"
#include "host/techniques/Registry.hpp"
#include "host/cl/ClRuntime.hpp"
#include "host/hashed/HashedAssigner.hpp"
#include "host/hashed/HashedStructure.hpp"
#include "host/scene/LightAnimator.hpp"
#include "host/util/Error.hpp"
#include "host/bench/BenchInputs.hpp"
#include "host/bench/OutputFiles.hpp"
#include "BenchCommon.hpp"

namespace {
using namespace ml;
using benchutil::Clock;
using benchutil::median;
using json = nlohmann::ordered_json;

// Process CPU time (all threads), ms: less sensitive than wall time to other
// processes on a shared machine.
double cpuMs() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return double(t.tv_sec) * 1e3 + double(t.tv_nsec) * 1e-6;
}

double mib(double bytes) { return bytes / (1024.0 * 1024.0); }

// The thesis suite's Spaceship Indoor scene where the tests look for the suite
// (tests/suite_thesis_test.cpp): $MANYLIGHTS_THESIS_SUITE, else the shared
// data folder next to the checkout. No machine's absolute path.
std::string defaultSuiteScene() {
  std::filesystem::path root = std::filesystem::path(MANYLIGHTS_SOURCE_DIR) / ".." / "shared" / "data" / "thesis-suite";
  if (const char* env = std::getenv("MANYLIGHTS_THESIS_SUITE"); env && *env) root = env;
  return (root / "scenes" / "spaceship-indoor").lexically_normal().string();
}

struct BuildRecord {
  hashed::BuildStats stats;  // the median-total run
  std::vector<hashed::LayerStats> layers;
  std::size_t table_bytes = 0, list_entries = 0, gpu_bytes = 0;
  unsigned depth = 0, layer_count = 0;
  double cell = 0;
  std::uint64_t failed_attempts = 0, rejected = 0;
  double cpu_ms = 0;  // process CPU time of the build, all threads
};

BuildRecord timedBuild(const std::vector<gpu::PointLight>& lights, const hashed::HashedConfig& cfg, const Scene* scene,
                       int reps) {
  std::vector<std::pair<double, BuildRecord>> runs;
  for (int i = 0; i < reps; ++i) {
    hashed::HashedStructure hs(cfg, scene);
    const double c0 = cpuMs();
    hs.build(lights);
    const double c1 = cpuMs();
    BuildRecord r;
    r.cpu_ms = c1 - c0;
    r.stats = hs.lastBuild();
    r.layers = hs.linkless().layerStats();
    r.table_bytes = hs.linkless().tableBytes();
    r.list_entries = hs.linkless().pool().list().size();
    r.gpu_bytes = hs.linkless().gpuBytes();
    r.depth = hs.bounds().depth;
    r.layer_count = hs.linkless().layerCount();
    r.cell = hs.bounds().cell_size;
    for (const auto& l : r.layers) {
      r.failed_attempts += (l.desc_attempts - 1) + (l.data_attempts - 1);
      r.rejected += l.rejected_candidates;
    }
    runs.emplace_back(r.stats.total_ms, r);
  }
  std::sort(runs.begin(), runs.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  return runs[runs.size() / 2].second;
}

json buildJson(const BuildRecord& r) {
  json layers = json::array();
  for (const auto& l : r.layers)
    layers.push_back({{"depth", l.depth}, {"branches", l.desc_keys}, {"filled_leaves", l.data_keys},
                      {"desc_slots", l.desc_slots}, {"data_slots", l.data_slots}, {"desc_offsets", l.desc_offsets},
                      {"data_offsets", l.data_offsets}, {"bytes", l.bytes}, {"desc_attempts", l.desc_attempts},
                      {"data_attempts", l.data_attempts}, {"rejected_candidates", l.rejected_candidates},
                      {"hash_ms", l.hash_ms}});
  const auto& s = r.stats;
  return {{"cell_size", r.cell},
          {"depth", r.depth},
          {"layers", r.layer_count},
          {"cpu_ms", r.cpu_ms},
          {"ms", {{"total", s.total_ms}, {"bounds", s.bounds_ms}, {"geometry_mask", s.mask_ms},
                  {"light_octrees", s.light_octrees_ms}, {"merge", s.merge_ms}, {"normalize", s.normalize_ms},
                  {"hashes", s.hash_ms}}},
          {"filled_cells", s.filled_cells},
          {"scene_nodes", s.scene_nodes},
          {"table_bytes", r.table_bytes},
          {"index_list_entries", r.list_entries},
          {"unshared_index_entries", s.leaf_index_entries},
          {"gpu_bytes", r.gpu_bytes},
          {"failed_attempts", r.failed_attempts},
          {"rejected_candidates", r.rejected},
          {"per_layer", layers}};
}

void printBuildHeader() {
  std::printf("%-8s %-6s %6s %3s %8s %8s %8s %8s %8s %8s %8s %9s %9s %9s %6s\n", "lights", "node", "cell", "L",
              "total ms", "cpu ms", "octrees", "merge", "normal.", "hashes", "nodes", "tables MiB", "list MiB", "GPU MiB",
              "fails");
}
void printBuild(const std::string& lights, const std::string& node, const BuildRecord& r) {
  const auto& s = r.stats;
  std::printf("%-8s %-6s %6.3f %3u %8.2f %8.2f %8.2f %8.2f %8.2f %8.2f %8zu %9.3f %9.3f %9.3f %6llu\n",
              lights.c_str(), node.c_str(), r.cell, r.depth, s.total_ms, r.cpu_ms, s.light_octrees_ms, s.merge_ms, s.normalize_ms, s.hash_ms,
              s.scene_nodes, mib(double(r.table_bytes)), mib(double(r.list_entries) * 4), mib(double(r.gpu_bytes)),
              static_cast<unsigned long long>(r.failed_attempts));
}

int run(int argc, char** argv) {
  CLI::App app{"Hashed shading: build, memory, light evaluations and dynamic updates"};
  std::string json_path, light_counts = "1024,4096", node_sizes = "0.25r,0.5r,1r,2r", size = "640x360";
  std::string suite_dir = defaultSuiteScene();
  // "tiled-deferred@32/none": the thesis's tiled baseline (32x32 tiles, no depth bounds).
  std::string compare = "tiled-deferred,tiled-deferred@32/none,clustered-deferred", device;
  std::string update_fractions = "0.01,0.1,1";
  int reps = 3, update_reps = 5;
  float light_density = 0.0f;
  unsigned camera_frames = 4;
  bool no_render = false, no_octant_masks = false;
  app.add_option("--json", json_path, "write records as JSON");
  app.add_option("--lights", light_counts, "generated light counts in the default scene")->capture_default_str();
  app.add_option("--light-density", light_density, kLightDensityHelp)->check(finitePositive());
  app.add_option("--node-sizes", node_sizes, "node sizes to sweep")->capture_default_str();
  app.add_option("--size", size, "render resolution for light evaluations")->capture_default_str();
  app.add_option("--camera-frames", camera_frames, "camera path frames averaged")->capture_default_str();
  app.add_option("--compare", compare, "techniques counted in the same run ('' for none)")->capture_default_str();
  app.add_option("--reps", reps, "builds per case (median reported)")->capture_default_str();
  app.add_option("--update-reps", update_reps, "updates per case (median reported)")->capture_default_str();
  app.add_option("--update-fractions", update_fractions, "fractions of the lights moving per update")
      ->capture_default_str();
  app.add_option("--suite", suite_dir, "thesis suite scene folder (its lights/ holds the 1890-light set)")
      ->capture_default_str();
  app.add_option("--device", device, "OpenCL device");
  app.add_flag("--no-render", no_render, "host-side sections only");
  app.add_flag("--no-octant-masks", no_octant_masks, "updates: the thesis's plain light lists (HashedConfig::octant_masks off)");
  CLI11_PARSE(app, argc, argv);
  benchutil::requireWritable("--json", json_path);
  unsigned width = 0, height = 0;
  parseSize(size, "--size", width, height);

  json out;
  out["tool"] = "manylights-hashed-bench";
  out["cpu_threads"] = std::thread::hardware_concurrency();

  SceneInputArgs scene_args;
  scene_args.lights = "1";
  const SceneInputs base = loadSceneInputs(scene_args);
  std::vector<std::pair<std::string, std::vector<gpu::PointLight>>> light_sets;
  for (const auto& c : splitList(light_counts)) {
    SceneInputArgs a;
    a.lights = c;
    a.light_density = light_density;
    light_sets.emplace_back(c, loadSceneInputs(a).lights);
  }

  // --- 1. Build time, memory, table sizes vs node size and light count ---
  std::printf("\n1. Build (default scene, generated lights; median of %d; times in ms; +g: geometry mask; "
              "-o: no octant masks)\n", reps);
  printBuildHeader();
  json builds = json::array();
  for (const auto& [label, lights] : light_sets)
    for (const auto& node : splitList(node_sizes)) {
      hashed::HashedConfig cfg;
      cfg.node_size = node;
      const BuildRecord r = timedBuild(lights, cfg, nullptr, reps);
      printBuild(label, node, r);
      cfg.octant_masks = false;
      const BuildRecord o = timedBuild(lights, cfg, nullptr, reps);
      printBuild(label, node + "-o", o);
      cfg.octant_masks = true;
      cfg.geometry_mask = true;
      const BuildRecord m = timedBuild(lights, cfg, &base.scene, reps);
      printBuild(label, node + "+g", m);
      builds.push_back({{"lights", lights.size()}, {"node_size", node}, {"plain", buildJson(r)},
                        {"no_octant_masks", buildJson(o)}, {"geometry_mask", buildJson(m)},
                        {"geometry_mask_memory_ratio", double(m.gpu_bytes) / double(r.gpu_bytes)},
                        {"octant_masks_memory_ratio", double(r.gpu_bytes) / double(o.gpu_bytes)}});
    }
  out["builds"] = builds;

  const std::string suite_lights = suite_dir + "/lights/1890#3x_3y_3z.json";
  const bool have_suite = std::filesystem::exists(suite_lights);
  auto update_sets = light_sets;
  if (have_suite) update_sets.emplace_back("suite1890", loadLightsJson(suite_lights));

  // --- 2. Incremental updates vs full rebuild ---
  std::printf("\n2. Updates (0.5r; lights move up to r/4; median of %d; ms; each update followed by a full build of the "
              "same lights (rebuild); min ratio: fastest update / fastest rebuild)\n", update_reps);
  std::printf("%-9s %7s %10s %10s %8s %9s %9s %8s %8s %8s %9s %9s\n", "lights", "moving", "update", "rebuild", "ratio",
              "cpu ratio", "min ratio", "octrees", "tree", "sync", "rehashed", "re-offset");
  json updates = json::array();
  for (const auto& [label, lights0] : update_sets) {
    hashed::HashedConfig cfg;
    cfg.node_size = "0.5r";
    cfg.max_incremental_fraction = 1.0;  // measure the incremental path itself
    cfg.octant_masks = !no_octant_masks;
    for (const auto& fraction_text : splitList(update_fractions)) {
      const double fraction = std::stod(fraction_text);
      // The same motion as --animate: distinct lights, steps of up to r/4,
      // staying within r/2 of their start.
      LightAnimator anim(lights0, fraction);
      hashed::HashedStructure hs(cfg);
      hs.build(lights0);
      std::vector<double> total, oct, tree, sync, cpu, rebuild_ms, rebuild_cpu;
      std::size_t rehashed = 0, reoffset = 0, full = 0;
      for (int i = 0; i < update_reps; ++i) {
        const auto& lights = anim.step();
        const double c0 = cpuMs();
        const auto& st = hs.update(lights);
        cpu.push_back(cpuMs() - c0);
        // Each update's peer: a full build of the same lights, right after
        // it, so that both see the same machine (its speed here drifts by
        // up to a third within seconds) and the same cold caches.
        {
          hashed::HashedStructure fresh(cfg);
          const double r0 = cpuMs();
          fresh.build(lights);
          rebuild_cpu.push_back(cpuMs() - r0);
          rebuild_ms.push_back(fresh.lastBuild().total_ms);
        }
        full += st.full_rebuild;
        total.push_back(st.total_ms);
        oct.push_back(st.light_octrees_ms);
        tree.push_back(st.tree_ms);
        sync.push_back(st.sync_ms);
        rehashed += st.sync.rehashed_tables;
        reoffset += st.sync.reoffsets;
      }
      const double rebuild = median(rebuild_ms), rebuild_c = median(rebuild_cpu);
      const double rebuild_min = *std::min_element(rebuild_ms.begin(), rebuild_ms.end());
      const double upd = median(total), upd_c = median(cpu);
      const double upd_min = *std::min_element(total.begin(), total.end());
      std::printf("%-9s %6.0f%% %10.2f %10.2f %7.1f%% %8.1f%% %8.1f%% %8.2f %8.2f %8.2f %9zu %9zu%s\n", label.c_str(),
                  fraction * 100, upd, rebuild, 100.0 * upd / rebuild, 100.0 * upd_c / rebuild_c,
                  100.0 * upd_min / rebuild_min, median(oct),
                  median(tree), median(sync), rehashed, reoffset, full ? "  (some left the bounds: rebuilt)" : "");
      updates.push_back({{"lights", lights0.size()}, {"fraction", fraction}, {"moved_per_update", anim.movesPerStep()}, {"update_ms", upd},
                         {"rebuild_ms", rebuild}, {"ratio", upd / rebuild}, {"update_min_ms", upd_min},
                         {"rebuild_min_ms", rebuild_min}, {"min_ratio", upd_min / rebuild_min},
                         {"update_cpu_ms", upd_c}, {"rebuild_cpu_ms", rebuild_c}, {"cpu_ratio", upd_c / rebuild_c}, {"light_octrees_ms", median(oct)},
                         {"tree_ms", median(tree)}, {"sync_ms", median(sync)}, {"rehashed_tables", rehashed},
                         {"reoffset_groups", reoffset}, {"full_rebuilds", full}, {"updates", update_reps}});
    }
  }
  out["updates"] = updates;
  out["updates_octant_masks"] = !no_octant_masks;

  // --- 3. Thesis suite: the 1890-light Spaceship Indoor set ---
  std::printf("\n3. Thesis suite: Spaceship Indoor, 1890 lights\n");
  if (!have_suite) {
    std::printf("   SKIPPED: %s not found (the project does not ship the thesis suite)\n", reportPath(suite_lights).c_str());
    out["thesis_suite"] = {{"skipped", "missing " + reportPath(suite_lights)}};
  } else {
    const auto lights = loadLightsJson(suite_lights);
    printBuildHeader();
    json suite = json::array();
    for (const auto& node : {"0.25r", "0.5r", "1r"}) {
      hashed::HashedConfig cfg;
      cfg.node_size = node;
      const BuildRecord r = timedBuild(lights, cfg, nullptr, std::max(reps, 5));
      printBuild(std::to_string(lights.size()), node, r);
      suite.push_back({{"lights", lights.size()}, {"node_size", node}, {"build", buildJson(r)}});
    }
    out["thesis_suite"] = suite;
  }

  // --- 4. Light evaluations per shaded pixel (same run: tiled, clustered) ---
  if (!no_render) {
    auto gl = createHeadlessContext();
    const auto share = gl->shareHandles();
    auto rt = ClRuntime::create(DeviceChoice::resolve(device), &share);
    std::printf("\n4. Light evaluations per covered pixel, deferred, %ux%u, %u camera frames; +g: geometry mask, -o: no octant masks\n%s\n%s\n", width, height,
                camera_frames, rt->describe().c_str(), gl->describe().c_str());
    std::printf("%-8s %-24s %12s %12s %10s %10s %12s\n", "lights", "technique", "evals/px", "bound/px",
                "x bound", "x tiled", "memory MiB");
    FrameRenderer r(*rt, base.scene, width, height);
    const auto& path = base.cameras.frames;
    std::vector<const Camera*> cams;
    for (unsigned i = 0; i < camera_frames; ++i)
      cams.push_back(&path[std::size_t(i) * path.size() / std::max(1u, camera_frames)]);
    json evals = json::array();
    for (const auto& [label, lights] : light_sets) {
      r.setLights(lights);
      using Given = std::vector<std::pair<std::string, std::string>>;  // technique parameters, by key
      std::vector<std::pair<std::string, Given>> runs;
      for (const auto& t : splitList(compare)) {
        Given p;
        if (const auto at = t.find('@'); at != std::string::npos) {
          const auto slash = t.find('/', at);
          p.emplace_back("tile", t.substr(at + 1, slash - at - 1));
          if (slash != std::string::npos) p.emplace_back("tile_depth", t.substr(slash + 1));
        }
        runs.emplace_back(t, p);
      }
      for (const auto& node : splitList(node_sizes))
        for (const bool mask : {false, true})
          for (const bool octants : {true, false}) {
            const Given p = {{"node_size", node}, {"geometry_mask", mask ? "on" : "off"},
                             {"octant_masks", octants ? "on" : "off"}};
            runs.emplace_back("hashed-deferred " + node + (mask ? "+g" : "") + (octants ? "" : "-o"), p);
          }
      double tiled_px = 0;
      for (const auto& [name, params] : runs) {
        const std::string tech = name.substr(0, std::min(name.find(' '), name.find('@')));
        std::unique_ptr<LightAssigner> a;
        try {
          const TechniqueInfo& info = findTechnique(tech, "--compare");
          a = makeAssigner(info, *rt, techniqueParams(info, params, "--compare"), &base.scene);
        } catch (const UserError& e) {
          std::printf("%-8s %-24s skipped: %s\n", label.c_str(), name.c_str(), e.what());
          continue;
        }
        std::uint64_t ev = 0, lb = 0, px = 0;
        std::size_t mem = 0;
        for (const Camera* c : cams) {
          const FrameResult fr = r.render(*c, *a, {Pipeline::Deferred, true});
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
        evals.push_back({{"lights", lights.size()}, {"technique", name}, {"evaluations_per_pixel", per_px},
                         {"lower_bound_per_pixel", bound_px}, {"ratio_to_bound", per_px / bound_px},
                         {"ratio_to_tiled", tiled_px > 0 ? per_px / tiled_px : 0.0}, {"memory_bytes", mem},
                         {"covered_pixels", px}});
      }
    }
    out["light_evaluations"] = evals;
  }

  benchutil::writeJson(json_path, out);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  return ml::benchutil::benchMain("manylights-hashed-bench", [&] { return run(argc, argv); });
}
