// manylights-clustered-bench: clustered shading on the CL device, per pass.
//   1. cluster keys + unique clusters, the three methods side by side
//      (page table, radix sort + unique, per-tile bitonic sort), per resolution;
//   2. the clusters' boxes (explicit bounds from the pixels by default, made
//      once per frame) and light assignment to the unique clusters, BVH vs
//      brute force (count + scan + fill, BVH build included), per resolution
//      and light count, with the device time of each pass;
//   3. whole frames, clustered vs tiled (forward and deferred): per-pass times,
//      light evaluations per shaded pixel against the exact lower bound.
// Depth buffers are the default scene's view at each resolution. Prints tables
// and, with --json, writes one record per case.
#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <fstream>

#include "gl/FrameRenderer.hpp"
#include "gl/GlContext.hpp"
#include "host/app/InputChecks.hpp"
#include "host/app/RenderCommand.hpp"
#include "host/app/SceneInputs.hpp"
#include "host/cl/ClRuntime.hpp"
#include "host/clustered/ClusteredAssigner.hpp"
#include "host/tiled/TiledAssigner.hpp"
#include "host/util/Error.hpp"
#include "host/bench/BenchInputs.hpp"
#include "BenchCommon.hpp"

namespace {
using namespace ml;
using benchutil::Clock;
using benchutil::median;
using benchutil::timeMedian;

// Levels of a BVH of branching 32 over ceil(n / leaf) leaves (leaves included).
unsigned levelsFor(std::uint32_t n, unsigned leaf) {
  if (n == 0) return 0;
  unsigned levels = 1;
  for (std::uint32_t c = (n + leaf - 1) / leaf; c > 32; c = (c + 31) / 32) ++levels;
  return levels;
}

int run(int argc, char** argv) {
  CLI::App app{"Clustered shading: unique-cluster methods, BVH vs brute-force assignment, frames vs tiled"};
  std::string json_path, sizes = "320x320,1280x720,1920x1080", light_counts = "1000,10000,100000";
  std::string frame_sizes = "320x320,1280x720", frame_lights = "1000,10000", leaf_sizes = "8,32";
  unsigned tile = 0, tiled_tile = 16;
  unsigned brute_max = 100000;
  float light_radius = 0.0f, light_density = 0.0f;
  bool key_order = false;
  int reps = 5;
  std::string device, bounds = "pixels";
  app.add_option("--json", json_path, "write records as JSON");
  app.add_option("--cluster-bounds", bounds, "cluster boxes: pixels (explicit) or frustum (implicit)")
      ->capture_default_str();
  app.add_option("--sizes", sizes, "resolutions of the per-pass cases")->capture_default_str();
  app.add_option("--lights", light_counts, "light counts of the assignment cases")->capture_default_str();
  app.add_option("--frame-sizes", frame_sizes, "resolutions of the frame comparisons ('' for none)")->capture_default_str();
  app.add_option("--frame-lights", frame_lights, "light counts of the frame comparisons")->capture_default_str();
  app.add_option("--cluster-tile", tile, "cluster tile size; 0: auto per resolution (32 from 720 lines up, 16 below)")
      ->capture_default_str();
  app.add_option("--tile", tiled_tile, "tile size of the tiled peer in frames")->capture_default_str();
  app.add_option("--leaf-sizes", leaf_sizes, "lights per leaf of the assignment cases (8, 16, 32)")
      ->capture_default_str();
  app.add_option("--light-radius", light_radius,
                 "radius of the generated lights of the assignment cases (0: the scene's default)")
      ->capture_default_str();
  app.add_option("--light-density", light_density, kLightDensityHelp)->check(finitePositive());
  app.add_flag("--key-order", key_order,
               "assignment passes over the clusters in key order instead of tile-Morton order");
  app.add_option("--brute-max-lights", brute_max, "skip brute-force assignment above this many lights")->capture_default_str();
  app.add_option("--reps", reps, "timed repetitions (median reported)")->capture_default_str();
  app.add_option("--device", device, "OpenCL device");
  CLI11_PARSE(app, argc, argv);
  benchutil::requireWritable("--json", json_path);
  const bool bounds_pixels = parseClusterBounds(bounds) == ClusterBounds::Pixels;

  auto gl = createHeadlessContext();
  const auto share = gl->shareHandles();
  auto rt = ClRuntime::create(DeviceChoice::resolve(device), &share);
  std::printf("%s\n%s\n", rt->describe().c_str(), gl->describe().c_str());
  SceneInputArgs base;
  base.lights = "1";
  SceneInputs scene = loadSceneInputs(base);
  const Camera& camera = scene.cameras.frames.front();
  nlohmann::ordered_json records = nlohmann::ordered_json::array();
  auto& q = rt->queue();

  std::printf("\nKeys + unique clusters, %s bounds (ms, median of %d)\n", bounds.c_str(), reps);
  std::printf("%-11s %5s %9s %10s %10s %10s %10s\n", "resolution", "tile", "clusters", "keys", "pagetable", "sort",
              "tile-sort");
  for (const auto& size : splitList(sizes)) {
    unsigned w = 0, h = 0;
    parseSize(size, "--sizes", w, h);
    std::vector<float> depth;
    {
      FrameRenderer r(*rt, scene.scene, w, h);
      r.setLights({});
      TiledAssigner a(*rt, 16, TileDepthMode::MinMax);
      r.render(camera, a, {Pipeline::Deferred, false});
      depth = r.targets().readDepth(true);
    }
    const auto cam = camera.params(w, h);
    const ClusterGrid g = ClusterGrid::make(cam, tile ? tile : autoClusterTile(w, h));
    cl::Buffer dbuf(rt->context(), CL_MEM_READ_ONLY, depth.size() * 4);
    q.enqueueWriteBuffer(dbuf, CL_TRUE, 0, depth.size() * 4, depth.data());
    ClusterUniquer u(*rt, UniqueMethod::PageTable);
    const double t_keys = timeMedian(reps, [&] {
      u.keys(q, dbuf, cam, g);
      q.finish();
    });
    std::uint32_t counts[3] = {0, 0, 0};
    double t_unique[3] = {0, 0, 0};
    int mi = 0;
    for (UniqueMethod m : {UniqueMethod::PageTable, UniqueMethod::Sort, UniqueMethod::TileSort}) {
      u.setMethod(m);
      t_unique[mi] = timeMedian(reps, [&] {
        counts[mi] = u.unique(q, g);
        q.finish();
      });
      records.push_back({{"name", std::string("cluster_unique_") + uniqueMethodName(m)}, {"resolution", size},
                         {"n", w * h}, {"tile", g.tile_size}, {"seconds", t_unique[mi]},
                         {"items_per_second", w * h / t_unique[mi]}, {"clusters", counts[mi]}});
      ++mi;
    }
    if (counts[0] != counts[1] || counts[1] != counts[2]) throw std::runtime_error("unique methods disagree");
    records.push_back({{"name", "cluster_keys"}, {"resolution", size}, {"n", w * h}, {"tile", g.tile_size},
                       {"seconds", t_keys}, {"items_per_second", w * h / t_keys}, {"slices", g.slices}});
    std::printf("%-11s %5u %9u %10.3f %10.3f %10.3f %10.3f\n", size.c_str(), g.tile_size, counts[0], t_keys * 1e3,
                t_unique[0] * 1e3, t_unique[1] * 1e3, t_unique[2] * 1e3);

    u.setMethod(UniqueMethod::PageTable);
    const std::uint32_t clusters = u.unique(q, g);
    const ClusterPixels pixels{dbuf, u.clusterOf()};
    const ClusterPixels* px = bounds_pixels ? &pixels : nullptr;
    {
      // The boxes: once per frame, whatever the assignment method.
      ClusterLightAssigner a(*rt, ClusterAssignMethod::Bvh);
      const double t_boxes = timeMedian(reps, [&] {
        a.boxes(q, cam, g, u.uniqueKeys(), clusters, nullptr, px);
        q.finish();
      });
      std::printf("  cluster boxes (%s): %.3f ms\n", bounds.c_str(), t_boxes * 1e3);
      records.push_back({{"name", std::string("cluster_boxes_") + bounds}, {"resolution", size}, {"n", w * h},
                         {"clusters", clusters}, {"seconds", t_boxes}, {"items_per_second", w * h / t_boxes}});
    }
    std::printf("  assignment %-8s %5s %12s %12s %10s %12s %7s %10s %10s\n", "lights", "leaf", "bvh ms", "brute ms",
                "speed-up", "entries", "levels", "hit leaves", "cpu speed-up");
    for (const auto& ls : splitList(light_counts)) {
      SceneInputArgs args;
      args.lights = ls;
      args.light_radius = light_radius;
      args.light_density = light_density;
      const auto lights = loadSceneInputs(args).lights;
      const auto n = std::uint32_t(lights.size());
      cl::Buffer lbuf(rt->context(), CL_MEM_READ_ONLY, std::max<std::size_t>(32, n * sizeof(gpu::PointLight)));
      if (n) q.enqueueWriteBuffer(lbuf, CL_TRUE, 0, n * sizeof(gpu::PointLight), lights.data());
      cl::Buffer ranges(rt->context(), CL_MEM_READ_WRITE, std::max<std::size_t>(16, clusters * 8));
      cl::Buffer list_records, leaf_lights;
      std::size_t cap = 0, leaf_cap = 0;
      // Lights -> clusters: count (BVH build included) + scan + fill (hit
      // records copied into place, leaf slots' light ids), the boxes made beforehand.
      auto run_assign = [&](ClusterLightAssigner& a, std::uint32_t& total, ClPassTimer* timer) {
        total = a.assign(q, lbuf, n, cam, timer);
        if (std::size_t(total) * 8 + 16 > cap) {
          cap = std::size_t(total) * 12 + 16;
          list_records = cl::Buffer(rt->context(), CL_MEM_READ_WRITE, cap);
        }
        if (a.leafLightSlots() * 4 + 16 > leaf_cap) {
          leaf_cap = a.leafLightSlots() * 4 + 16;
          leaf_lights = cl::Buffer(rt->context(), CL_MEM_READ_WRITE, leaf_cap);
        }
        a.fill(q, ranges, list_records, leaf_lights, timer);
        q.finish();
      };
      struct Timed {
        double seconds = 0, cpu_seconds = 0;
        std::uint32_t total = 0;  // records (hit leaves)
        std::uint64_t listed = 0;  // lights in the lists
      };
      auto time_assign = [&](ClusterLightAssigner& a) {
        Timed r;
        a.boxes(q, cam, g, u.uniqueKeys(), clusters, nullptr, px);
        const benchutil::WallCpu t = benchutil::timeMedianWallCpu(reps, [&] { run_assign(a, r.total, nullptr); });
        r.seconds = t.wall;
        r.cpu_seconds = t.cpu;
        // One more run for the device time of each pass.
        ClPassTimer timer;
        run_assign(a, r.total, &timer);
        PassTimings passes;
        timer.collect(passes);
        std::printf("    %s leaf %u passes (device ms):", clusterAssignName(a.method()), a.leafSize());
        for (const auto& [name, ms] : passes.entries()) std::printf(" %s=%.2f", name.c_str(), ms);
        r.listed = a.listedLights(q);
        std::printf(" | hit leaves %u (%.1f lights each)\n", r.total,
                    r.total ? double(r.listed) / double(r.total) : 0.0);
        return r;
      };
      // Each leaf size: the BVH and brute force (the same leaf test over
      // every leaf). The speed-up is against the fastest brute force of the
      // run, so a leaf size that suits the BVH cannot slow its peer down.
      std::vector<std::pair<unsigned, Timed>> bvh_runs, brute_runs;
      for (const auto& lsz : splitList(leaf_sizes)) {
        const unsigned leaf = unsigned(std::stoul(lsz));
        ClusterLightAssigner bvh(*rt, ClusterAssignMethod::Bvh, leaf), brute(*rt, ClusterAssignMethod::Brute, leaf);
        // Record slots for every leaf of every cluster (up to 2^25, 256 MB), so
        // that neither method walks again in the fill pass: brute force, with
        // its unsorted leaves, has many more hit leaves than the BVH and would
        // otherwise be the one that overflows the default budget.
        const std::size_t all_leaves = std::size_t(clusters) * ((n + bvh.leafSize() - 1) / bvh.leafSize());
        for (ClusterLightAssigner* a : {&bvh, &brute}) {
          a->setRecordBudget(std::min<std::size_t>(all_leaves, 1u << 25));
          a->setClusterOrder(!key_order);
        }
        bvh_runs.emplace_back(bvh.leafSize(), time_assign(bvh));
        if (n <= brute_max) {
          brute_runs.emplace_back(brute.leafSize(), time_assign(brute));
          if (brute_runs.back().second.listed != bvh_runs.back().second.listed)
            throw std::runtime_error("BVH and brute force disagree on the list size");
        }
      }
      double best_brute = 0, best_brute_cpu = 0;
      for (const auto& [leaf, r] : brute_runs) {
        if (best_brute == 0 || r.seconds < best_brute) best_brute = r.seconds;
        if (best_brute_cpu == 0 || r.cpu_seconds < best_brute_cpu) best_brute_cpu = r.cpu_seconds;
      }
      for (std::size_t i = 0; i < bvh_runs.size(); ++i) {
        const auto& [leaf, b] = bvh_runs[i];
        const double t_brute = i < brute_runs.size() ? brute_runs[i].second.seconds : 0.0;
        std::printf("  %-11s %8u %5u %12.3f %12s %10s %12u %7u %10llu %10s\n", size.c_str(), n, leaf, b.seconds * 1e3,
                    t_brute > 0 ? std::to_string(t_brute * 1e3).c_str() : "-",
                    best_brute > 0 ? (std::to_string(best_brute / b.seconds) + "x").c_str() : "-",
                    unsigned(b.listed), levelsFor(n, leaf), static_cast<unsigned long long>(b.total),
                    best_brute_cpu > 0 ? (std::to_string(best_brute_cpu / b.cpu_seconds) + "x").c_str() : "-");
        records.push_back({{"name", "cluster_assign_bvh"}, {"resolution", size}, {"n", n}, {"lights", n},
                           {"leaf_size", leaf}, {"clusters", clusters}, {"seconds", b.seconds},
                           {"cpu_seconds", b.cpu_seconds},
                           {"items_per_second", n / b.seconds}, {"list_entries", b.listed},
                           {"hit_leaves", b.total}, {"bvh_levels", levelsFor(n, leaf)},
                           {"cluster_bounds", bounds}});
        if (t_brute > 0)
          records.push_back({{"name", "cluster_assign_brute"}, {"resolution", size}, {"n", n}, {"lights", n},
                             {"leaf_size", leaf}, {"clusters", clusters}, {"seconds", t_brute},
                             {"cpu_seconds", brute_runs[i].second.cpu_seconds},
                             {"items_per_second", n / t_brute}, {"list_entries", brute_runs[i].second.listed},
                             {"hit_leaves", brute_runs[i].second.total},
                             {"speedup_bvh_vs_best_brute", best_brute / b.seconds},
                             {"cpu_speedup_bvh_vs_best_brute", best_brute_cpu / b.cpu_seconds}});
      }
    }
  }

  if (!frame_sizes.empty()) {
    std::printf("\nFrames (ms, median of %d; GL passes host-timed on software GL); evals/px and ratio to the exact lower bound\n",
                reps);
    for (const auto& size : splitList(frame_sizes)) {
      unsigned w = 0, h = 0;
      parseSize(size, "--frame-sizes", w, h);
      FrameRenderer r(*rt, scene.scene, w, h);
      for (const auto& ls : splitList(frame_lights)) {
        SceneInputArgs args;
        args.lights = ls;
        args.light_density = light_density;
        r.setLights(loadSceneInputs(args).lights);
        for (auto [tech, pipe] : {std::pair{"clustered-forward", Pipeline::Forward}, std::pair{"clustered-deferred", Pipeline::Deferred},
                                  std::pair{"tiled-forward", Pipeline::Forward}, std::pair{"tiled-deferred", Pipeline::Deferred}}) {
          std::unique_ptr<LightAssigner> a;
          if (std::string(tech).rfind("clustered", 0) == 0)
            a = std::make_unique<ClusteredAssigner>(*rt, tile, UniqueMethod::PageTable, ClusterAssignMethod::Bvh,
                                                    parseClusterBounds(bounds));
          else
            a = std::make_unique<TiledAssigner>(*rt, tiled_tile, TileDepthMode::MinMax);
          const FrameResult counted = r.render(camera, *a, {pipe, true});
          std::vector<FrameResult> frames;
          for (int i = 0; i < reps; ++i) frames.push_back(r.render(camera, *a, {pipe, false}));
          const double px = double(std::max<std::uint64_t>(1, counted.covered_pixels));
          const double ratio = double(counted.light_evaluations) / double(std::max<std::uint64_t>(1, counted.lower_bound));
          std::printf("%-11s %7s %-19s", size.c_str(), ls.c_str(), tech);
          nlohmann::ordered_json passes;
          double pass_sum = 0.0;
          for (const auto& [name, ms] : frames.front().passes.entries()) {
            (void)ms;
            std::vector<double> v;
            for (const auto& f : frames) v.push_back(f.passes.get(name));
            passes[name] = median(v);
            pass_sum += median(v);
            std::printf(" %s=%.2f", name.c_str(), median(v));
          }
          std::printf(" | sum=%.2f", pass_sum);
          std::vector<double> host;
          for (const auto& f : frames) host.push_back(f.host_ms);
          std::printf(" | frame=%.2f evals/px=%.2f lb/px=%.2f ratio=%.3f\n", median(host),
                      counted.light_evaluations / px, counted.lower_bound / px, ratio);
          records.push_back({{"name", std::string("frame_") + tech}, {"resolution", size}, {"lights", std::stoul(ls)},
                             {"n", std::stoul(ls)}, {"seconds", median(host) * 1e-3},
                             {"items_per_second", double(w) * h / (median(host) * 1e-3)}, {"passes", passes},
                             {"sum_of_passes_ms", pass_sum},
                             {"evals_per_pixel", counted.light_evaluations / px},
                             {"lower_bound_per_pixel", counted.lower_bound / px}, {"evals_over_lower_bound", ratio}});
        }
      }
    }
  }
  benchutil::writeJson(json_path, records);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  return ml::benchutil::benchMain("manylights-clustered-bench", [&] { return run(argc, argv); });
}
