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
#include <cstdio>
#include <memory>
#include <tuple>

#include "host/run/SceneInputs.hpp"
#include "host/cl/ClPassTimer.hpp"
#include "host/clustered/ClusteredAssigner.hpp"
#include "BenchCommon.hpp"
#include "BenchSupport.hpp"

namespace {
using namespace ml;
using benchutil::timeMedian;
using json = nlohmann::ordered_json;

struct Args {
  benchutil::BenchArgs common;
  std::string sizes = "320x320,1280x720,1920x1080", light_counts = "1000,10000,100000";
  std::string frame_sizes = "320x320,1280x720", frame_lights = "1000,10000", leaf_sizes = "8,32";
  std::string bounds = "pixels";
  unsigned tile = 0, tiled_tile = 16, brute_max = 100000;
  float light_radius = 0.0f;
  bool key_order = false;
};

// Levels of a BVH of branching 32 over ceil(n / leaf) leaves (leaves included).
unsigned levelsFor(std::uint32_t n, unsigned leaf) {
  if (n == 0) return 0;
  unsigned levels = 1;
  for (std::uint32_t c = (n + leaf - 1) / leaf; c > 32; c = (c + 31) / 32) ++levels;
  return levels;
}

// One resolution: the default view's depth, its cluster keys and unique clusters.
struct ClusterView {
  std::string size;
  unsigned w = 0, h = 0;
  gpu::CameraParams cam{};
  ClusterGrid g{};
  cl::Buffer depth;
  std::unique_ptr<ClusterUniquer> u;
  std::uint32_t clusters = 0;
  bool bounds_pixels = true;  // false: sub-frustum bounds
};

// The boxes of the view's unique clusters: from their pixels, or their sub-frusta.
void makeBoxes(cl::CommandQueue& q, const ClusterView& v, ClusterLightAssigner& a) {
  const ClusterPixels pixels{v.depth, v.u->clusterOf()};
  a.boxes(q, v.cam, v.g, v.u->uniqueKeys(), v.clusters, nullptr, v.bounds_pixels ? &pixels : nullptr);
}

// Section 1 for one resolution: keys and the three unique methods (a row, four records).
void timeUnique(const Args& a, ClRuntime& rt, ClusterView& v, json& records) {
  auto& q = rt.queue();
  const double t_keys = timeMedian(a.common.reps, [&] {
    v.u->keys(q, v.depth, v.cam, v.g);
    q.finish();
  });
  std::uint32_t counts[3] = {0, 0, 0};
  double t_unique[3] = {0, 0, 0};
  int mi = 0;
  for (UniqueMethod m : {UniqueMethod::PageTable, UniqueMethod::Sort, UniqueMethod::TileSort}) {
    v.u->setMethod(m);
    t_unique[mi] = timeMedian(a.common.reps, [&] {
      counts[mi] = v.u->unique(q, v.g);
      q.finish();
    });
    records.push_back({{"name", std::string("cluster_unique_") + uniqueMethodName(m)}, {"resolution", v.size},
                       {"n", v.w * v.h}, {"tile", v.g.tile_size}, {"seconds", t_unique[mi]},
                       {"items_per_second", v.w * v.h / t_unique[mi]}, {"clusters", counts[mi]}});
    ++mi;
  }
  if (counts[0] != counts[1] || counts[1] != counts[2]) throw std::runtime_error("unique methods disagree");
  records.push_back({{"name", "cluster_keys"}, {"resolution", v.size}, {"n", v.w * v.h}, {"tile", v.g.tile_size},
                     {"seconds", t_keys}, {"items_per_second", v.w * v.h / t_keys}, {"slices", v.g.slices}});
  std::printf("%-11s %5u %9u %10.3f %10.3f %10.3f %10.3f\n", v.size.c_str(), v.g.tile_size, counts[0], t_keys * 1e3,
              t_unique[0] * 1e3, t_unique[1] * 1e3, t_unique[2] * 1e3);
}

// The view of `size`, its unique clusters by page table (the frames' method), and its boxes timed.
ClusterView clusterView(benchutil::BenchSetup& b, const Args& a, const std::string& size, json& records) {
  ClusterView v;
  v.size = size;
  std::tie(v.w, v.h) = benchutil::sizeOf(size, "--sizes");
  const std::vector<float> depth = benchutil::viewDepth(b, v.w, v.h);
  v.cam = b.camera().params(v.w, v.h);
  v.g = ClusterGrid::make(v.cam, a.tile ? a.tile : autoClusterTile(v.w, v.h));
  v.depth = benchutil::uploadBuffer(b.cl(), depth.data(), depth.size() * 4, 0);
  v.u = std::make_unique<ClusterUniquer>(b.cl(), UniqueMethod::PageTable);
  timeUnique(a, b.cl(), v, records);
  v.u->setMethod(UniqueMethod::PageTable);
  auto& q = b.cl().queue();
  v.clusters = v.u->unique(q, v.g);
  v.bounds_pixels = parseClusterBounds(a.bounds) == ClusterBounds::Pixels;
  // The boxes: once per frame, whatever the assignment method.
  ClusterLightAssigner boxes(b.cl(), ClusterAssignMethod::Bvh);
  const double t_boxes = timeMedian(a.common.reps, [&] {
    makeBoxes(q, v, boxes);
    q.finish();
  });
  std::printf("  cluster boxes (%s): %.3f ms\n", a.bounds.c_str(), t_boxes * 1e3);
  records.push_back({{"name", std::string("cluster_boxes_") + a.bounds}, {"resolution", size}, {"n", v.w * v.h},
                     {"clusters", v.clusters}, {"seconds", t_boxes}, {"items_per_second", v.w * v.h / t_boxes}});
  return v;
}

// One light set's device buffers for assignment; the lists grow as needed.
struct AssignBuffers {
  cl::Buffer lights, ranges, list_records, leaf_lights;
  std::uint32_t n = 0;
  std::size_t cap = 0, leaf_cap = 0;
};

struct Timed {
  double seconds = 0, cpu_seconds = 0;
  std::uint32_t total = 0;   // records (hit leaves)
  std::uint64_t listed = 0;  // lights in the lists
};

// Lights -> clusters: count (BVH build included) + scan + fill (hit records
// copied into place, leaf slots' light ids), the boxes made beforehand.
void runAssign(ClRuntime& rt, const ClusterView& v, AssignBuffers& buf, ClusterLightAssigner& a, std::uint32_t& total,
               ClPassTimer* timer) {
  auto& q = rt.queue();
  total = a.assign(q, buf.lights, buf.n, v.cam, timer);
  if (std::size_t(total) * 8 + 16 > buf.cap) {
    buf.cap = std::size_t(total) * 12 + 16;
    buf.list_records = cl::Buffer(rt.context(), CL_MEM_READ_WRITE, buf.cap);
  }
  if (a.leafLightSlots() * 4 + 16 > buf.leaf_cap) {
    buf.leaf_cap = a.leafLightSlots() * 4 + 16;
    buf.leaf_lights = cl::Buffer(rt.context(), CL_MEM_READ_WRITE, buf.leaf_cap);
  }
  a.fill(q, buf.ranges, buf.list_records, buf.leaf_lights, timer);
  q.finish();
}

// Median wall and CPU time of runAssign, then one more run for each pass's device time.
Timed timeAssign(ClRuntime& rt, int reps, const ClusterView& v, AssignBuffers& buf, ClusterLightAssigner& a) {
  Timed r;
  makeBoxes(rt.queue(), v, a);
  const benchutil::WallCpu t = benchutil::timeMedianWallCpu(reps, [&] { runAssign(rt, v, buf, a, r.total, nullptr); });
  r.seconds = t.wall;
  r.cpu_seconds = t.cpu;
  ClPassTimer timer;
  runAssign(rt, v, buf, a, r.total, &timer);
  PassTimings passes;
  timer.collect(passes);
  std::printf("    %s leaf %u passes (ms):", clusterAssignName(a.method()), a.leafSize());
  std::printf("%s", passListText(passes).c_str());
  r.listed = a.listedLights(rt.queue());
  std::printf(" | hit leaves %u (%.1f lights each)\n", r.total, r.total ? double(r.listed) / double(r.total) : 0.0);
  return r;
}

using LeafRuns = std::vector<std::pair<unsigned, Timed>>;

// The rows and records of one light set: each leaf size's BVH against the
// fastest brute force of the run (so a leaf size that suits the BVH cannot
// slow its peer down), wall and CPU time.
void reportAssign(const Args& a, const ClusterView& v, std::uint32_t n, const LeafRuns& bvh_runs,
                  const LeafRuns& brute_runs, json& records) {
  double best = 0, best_cpu = 0;
  for (const auto& [leaf, r] : brute_runs) {
    if (best == 0 || r.seconds < best) best = r.seconds;
    if (best_cpu == 0 || r.cpu_seconds < best_cpu) best_cpu = r.cpu_seconds;
  }
  for (std::size_t i = 0; i < bvh_runs.size(); ++i) {
    const auto& [leaf, b] = bvh_runs[i];
    const double t_brute = i < brute_runs.size() ? brute_runs[i].second.seconds : 0.0;
    std::printf("  %-11s %8u %5u %12.3f %12s %10s %12u %7u %10llu %10s\n", v.size.c_str(), n, leaf, b.seconds * 1e3,
                t_brute > 0 ? std::to_string(t_brute * 1e3).c_str() : "-",
                best > 0 ? (std::to_string(best / b.seconds) + "x").c_str() : "-", unsigned(b.listed),
                levelsFor(n, leaf), static_cast<unsigned long long>(b.total),
                best_cpu > 0 ? (std::to_string(best_cpu / b.cpu_seconds) + "x").c_str() : "-");
    records.push_back({{"name", "cluster_assign_bvh"}, {"resolution", v.size}, {"n", n}, {"lights", n},
                       {"leaf_size", leaf}, {"clusters", v.clusters}, {"seconds", b.seconds},
                       {"cpu_seconds", b.cpu_seconds}, {"items_per_second", n / b.seconds},
                       {"list_entries", b.listed}, {"hit_leaves", b.total}, {"bvh_levels", levelsFor(n, leaf)},
                       {"cluster_bounds", a.bounds}});
    if (t_brute > 0)
      records.push_back({{"name", "cluster_assign_brute"}, {"resolution", v.size}, {"n", n}, {"lights", n},
                         {"leaf_size", leaf}, {"clusters", v.clusters}, {"seconds", t_brute},
                         {"cpu_seconds", brute_runs[i].second.cpu_seconds}, {"items_per_second", n / t_brute},
                         {"list_entries", brute_runs[i].second.listed}, {"hit_leaves", brute_runs[i].second.total},
                         {"speedup_bvh_vs_best_brute", best / b.seconds},
                         {"cpu_speedup_bvh_vs_best_brute", best_cpu / b.cpu_seconds}});
  }
}

// Section 2 for one resolution and light set: BVH and brute force (the same
// leaf test over every leaf) per leaf size.
void assignCase(benchutil::BenchSetup& b, const Args& a, const ClusterView& v, const std::string& ls, json& records) {
  const auto lights = benchutil::generatedLights(ls, a.common.light_density, a.light_radius);
  AssignBuffers buf;
  buf.n = std::uint32_t(lights.size());
  buf.lights = benchutil::uploadBuffer(b.cl(), lights.data(), buf.n * sizeof(gpu::PointLight), 32);
  buf.ranges = cl::Buffer(b.cl().context(), CL_MEM_READ_WRITE, std::max<std::size_t>(16, v.clusters * 8));
  LeafRuns bvh_runs, brute_runs;
  for (const auto& lsz : splitList(a.leaf_sizes)) {
    const unsigned leaf = unsigned(std::stoul(lsz));
    ClusterLightAssigner bvh(b.cl(), ClusterAssignMethod::Bvh, leaf), brute(b.cl(), ClusterAssignMethod::Brute, leaf);
    // Record slots for every leaf of every cluster (up to 2^25, 256 MB), so
    // that neither method walks again in the fill pass: brute force, with
    // its unsorted leaves, has many more hit leaves than the BVH and would
    // otherwise be the one that overflows the default budget.
    const std::size_t all_leaves = std::size_t(v.clusters) * ((buf.n + bvh.leafSize() - 1) / bvh.leafSize());
    for (ClusterLightAssigner* c : {&bvh, &brute}) {
      c->setRecordBudget(std::min<std::size_t>(all_leaves, 1u << 25));
      c->setClusterOrder(!a.key_order);
    }
    bvh_runs.emplace_back(bvh.leafSize(), timeAssign(b.cl(), a.common.reps, v, buf, bvh));
    if (buf.n <= a.brute_max) {
      brute_runs.emplace_back(brute.leafSize(), timeAssign(b.cl(), a.common.reps, v, buf, brute));
      if (brute_runs.back().second.listed != bvh_runs.back().second.listed)
        throw std::runtime_error("BVH and brute force disagree on the list size");
    }
  }
  reportAssign(a, v, buf.n, bvh_runs, brute_runs, records);
}

void parseArgs(CLI::App& app, Args& a) {
  benchutil::addBenchArgs(app, a.common);
  app.add_option("--cluster-bounds", a.bounds, "cluster boxes: pixels (explicit) or frustum (implicit)")
      ->capture_default_str();
  app.add_option("--sizes", a.sizes, "resolutions of the per-pass cases")->capture_default_str();
  app.add_option("--lights", a.light_counts, "light counts of the assignment cases")->capture_default_str();
  app.add_option("--frame-sizes", a.frame_sizes, "resolutions of the frame comparisons ('' for none)")
      ->capture_default_str();
  app.add_option("--frame-lights", a.frame_lights, "light counts of the frame comparisons")->capture_default_str();
  app.add_option("--cluster-tile", a.tile, "cluster tile size; 0: auto per resolution (32 from 720 lines up, 16 below)")
      ->capture_default_str();
  app.add_option("--tile", a.tiled_tile, "tile size of the tiled peer in frames")->capture_default_str();
  app.add_option("--leaf-sizes", a.leaf_sizes, "lights per leaf of the assignment cases (8, 16, 32)")
      ->capture_default_str();
  app.add_option("--light-radius", a.light_radius,
                 "radius of the generated lights of the assignment cases (0: the scene's default)")
      ->capture_default_str();
  app.add_flag("--key-order", a.key_order,
               "assignment passes over the clusters in key order instead of tile-Morton order");
  app.add_option("--brute-max-lights", a.brute_max, "skip brute-force assignment above this many lights")
      ->capture_default_str();
}

// Section 3: clustered and tiled frames, counted.
benchutil::FrameSweep frameSweep(const Args& a) {
  const std::vector<std::pair<std::string, std::string>> cp = {{"cluster_tile", std::to_string(a.tile)},
                                                                {"cluster_bounds", a.bounds}};
  const std::vector<std::pair<std::string, std::string>> tp = {{"tile", std::to_string(a.tiled_tile)},
                                                                {"tile_depth", "minmax"}};
  return {splitList(a.frame_sizes), splitList(a.frame_lights), a.common.light_density,
          {{"clustered-forward", cp}, {"clustered-deferred", cp}, {"tiled-forward", tp}, {"tiled-deferred", tp}},
          a.common.reps, true};
}

// The flags parsing leaves unchecked, checked before GL/CL open.
void checkArgs(const Args& a) {
  (void)parseClusterBounds(a.bounds);
  benchutil::checkSizes(a.sizes, "--sizes");
  benchutil::checkSizes(a.frame_sizes, "--frame-sizes");
}

int run(int argc, char** argv) {
  CLI::App app{"Clustered shading: unique-cluster methods, BVH vs brute-force assignment, frames vs tiled"};
  Args a;
  parseArgs(app, a);
  if (const auto stop = benchutil::parseCommandLine(app, argc, argv, a.common, [&] { checkArgs(a); })) return *stop;
  benchutil::BenchSetup b = benchutil::BenchSetup::open(a.common.device, benchutil::defaultScene());
  json records = json::array();

  std::printf("\nKeys + unique clusters, %s bounds (ms, median of %d)\n", a.bounds.c_str(), a.common.reps);
  std::printf("%-11s %5s %9s %10s %10s %10s %10s\n", "resolution", "tile", "clusters", "keys", "pagetable", "sort",
              "tile-sort");
  for (const auto& size : splitList(a.sizes)) {
    const ClusterView v = clusterView(b, a, size, records);
    std::printf("  assignment %-8s %5s %12s %12s %10s %12s %7s %10s %10s\n", "lights", "leaf", "bvh ms", "brute ms",
                "speed-up", "entries", "levels", "hit leaves", "cpu speed-up");
    for (const auto& ls : splitList(a.light_counts)) assignCase(b, a, v, ls, records);
  }
  if (!a.frame_sizes.empty()) {
    std::printf("\nFrames (ms, median of %d; GL passes host-timed on software GL); evals/px and ratio to the exact "
                "lower bound\n", a.common.reps);
    benchutil::runFrameSweep(b, frameSweep(a), records);
  }
  benchutil::writeJson(a.common.json_path, records);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  return ml::benchutil::benchMain("manylights-clustered-bench", [&] { return run(argc, argv); });
}
