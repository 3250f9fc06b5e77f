// manylights-tiled-bench: the OpenCL tile light culler against the plain C++
// culler (same algorithm and tests, multi-threaded with TBB) and against the
// previous OpenCL culler (TileCullAlgorithm::PairAtomics: an atomic per list
// entry; --no-legacy skips it) on the same device, depth buffer and lights, in
// one run, all three held to the same list total; plus per-pass frame
// breakdowns of tiled forward/deferred. Prints a table and, with --json, writes one record
// per case: name, resolution, lights, seconds (median), items_per_second.
#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cstdio>

#include "host/run/SceneInputs.hpp"
#include "host/cl/ClPassTimer.hpp"
#include "host/tiled/TileCullerReference.hpp"
#include "host/tiled/TileLightCuller.hpp"
#include "host/tiled/TiledAssigner.hpp"
#include "BenchCommon.hpp"
#include "BenchSupport.hpp"

namespace {
using namespace ml;
using benchutil::timeMedian;

struct Args {
  benchutil::BenchArgs common;
  std::string sizes = "320x320,1280x720,1920x1080", light_counts = "1000,10000,100000";
  std::string frame_sizes = "320x320,1280x720", frame_lights = "1000,10000", depth_mode = "minmax";
  unsigned tile = 16;
  bool no_legacy = false, passes = false;
};

// One culling case's device inputs: lights, depth, the tile grid and a growing index list.
struct CullInputs {
  cl::Buffer lights, depth, grid, indices;
  std::uint32_t n = 0;
  std::size_t cap = 0;
  gpu::CameraParams cam;
};

// Median seconds of count + fill with `algo`; `total` gets the list size.
double timeCuller(ClRuntime& rt, const Args& a, CullInputs& in, TileCullAlgorithm algo, std::uint32_t& total) {
  TileLightCuller culler(rt, a.tile, parseTileDepthMode(a.depth_mode), KernelShape::Auto, algo);
  auto& q = rt.queue();
  ClPassTimer timer;
  ClPassTimer* tp = a.passes ? &timer : nullptr;
  PassTimings pt;
  const double t = timeMedian(a.common.reps, [&] {
    pt = PassTimings{};
    total = culler.count(q, in.lights, in.n, in.cam, &in.depth, tp);
    if (std::size_t(total) * 4 > in.cap) {
      in.cap = std::max<std::size_t>(16, std::size_t(total) * 4 * 3 / 2);
      in.indices = cl::Buffer(rt.context(), CL_MEM_READ_WRITE, in.cap);
    }
    culler.fill(q, in.lights, in.n, in.cam, in.grid, in.indices, tp);
    q.finish();
    if (tp) timer.collect(pt);
  });
  if (tp) {
    std::printf("  %s passes:", algo == TileCullAlgorithm::PairAtomics ? "old" : "new");
    std::printf("%s", passListText(pt).c_str());
    std::printf("\n");
  }
  return t;
}

// The three cullers on one resolution's depth and one light set: a row and three records.
void cullCase(benchutil::BenchSetup& b, const Args& a, const std::string& size, const std::vector<float>& depth,
              const std::string& ls, nlohmann::ordered_json& records) {
  const auto [w, h] = benchutil::sizeOf(size, "--sizes");
  const auto lights = benchutil::generatedLights(ls, a.common.light_density);
  CullInputs in;
  in.n = std::uint32_t(lights.size());
  in.cam = b.camera().params(w, h);
  in.lights = benchutil::uploadBuffer(b.cl(), lights.data(), in.n * sizeof(gpu::PointLight));
  in.depth = benchutil::uploadBuffer(b.cl(), depth.data(), depth.size() * 4);
  const TileGrid g{a.tile, w, h};
  in.grid = cl::Buffer(b.cl().context(), CL_MEM_READ_WRITE, std::size_t(g.count()) * 8);
  std::uint32_t total = 0, legacy_total = 0;
  const double t_kernel = timeCuller(b.cl(), a, in, TileCullAlgorithm::ChunkCounts, total);
  const double t_legacy = a.no_legacy ? 0.0 : timeCuller(b.cl(), a, in, TileCullAlgorithm::PairAtomics, legacy_total);
  if (!a.no_legacy && legacy_total != total) throw std::runtime_error("new and old kernels disagree on the list size");
  std::size_t ref_total = 0;
  const TileDepthMode mode = parseTileDepthMode(a.depth_mode);
  const double t_ref = timeMedian(a.common.reps, [&] {
    ref_total = cullTilesReference(lights, depth.data(), in.cam, g, mode, true).indices.size();
  });
  if (ref_total != total) throw std::runtime_error("kernel and C++ culler disagree on the list size");
  std::printf("%-11s %8u %12.3f %12.3f %12.3f %9.2fx %9.2fx %12u\n", size.c_str(), in.n, t_kernel * 1e3,
              t_legacy * 1e3, t_ref * 1e3, t_ref / t_kernel, t_legacy / t_kernel, total);
  std::vector<std::pair<const char*, double>> timed{{"tile_cull_opencl", t_kernel}, {"tile_cull_cpp_tbb", t_ref}};
  if (!a.no_legacy) timed.emplace_back("tile_cull_opencl_pair_atomics", t_legacy);
  for (auto [name, t] : timed)
    records.push_back({{"name", name}, {"resolution", size}, {"n", in.n}, {"lights", in.n}, {"tile", a.tile},
                       {"depth_mode", a.depth_mode}, {"seconds", t}, {"items_per_second", in.n / t},
                       {"bytes_per_second", (depth.size() * 4.0 + in.n * 32.0) / t}, {"list_entries", total},
                       {"speedup_vs_cpp", t_ref / t_kernel}});
}

void parseArgs(CLI::App& app, Args& a) {
  benchutil::addBenchArgs(app, a.common);
  app.add_flag("--no-legacy", a.no_legacy, "skip the previous (per-entry atomics) kernel");
  app.add_flag("--passes", a.passes, "print the culler's per-pass device times (last repetition)");
  app.add_option("--sizes", a.sizes, "culling resolutions")->capture_default_str();
  app.add_option("--lights", a.light_counts, "culling light counts")->capture_default_str();
  app.add_option("--frame-sizes", a.frame_sizes, "resolutions of the frame breakdowns ('' for none)")
      ->capture_default_str();
  app.add_option("--frame-lights", a.frame_lights, "light counts of the frame breakdowns")->capture_default_str();
  app.add_option("--tile", a.tile, "tile size")->capture_default_str();
  app.add_option("--tile-depth", a.depth_mode, "none|minmax|mask")->capture_default_str();
}

// The flags parsing leaves unchecked, checked before GL/CL open.
void checkArgs(const Args& a) {
  (void)parseTileDepthMode(a.depth_mode);
  benchutil::checkSizes(a.sizes, "--sizes");
  benchutil::checkSizes(a.frame_sizes, "--frame-sizes");
}

int run(int argc, char** argv) {
  CLI::App app{"Tile light culling: OpenCL kernel vs multi-threaded C++, and tiled frame breakdowns"};
  Args a;
  parseArgs(app, a);
  if (const auto stop = benchutil::parseCommandLine(app, argc, argv, a.common, [&] { checkArgs(a); })) return *stop;
  benchutil::BenchSetup b = benchutil::BenchSetup::open(a.common.device, benchutil::defaultScene());
  nlohmann::ordered_json records = nlohmann::ordered_json::array();

  std::printf("\nTile light culling, tile %u, depth %s (median of %d)\n", a.tile, a.depth_mode.c_str(), a.common.reps);
  std::printf("%-11s %8s %12s %12s %12s %10s %10s %12s\n", "resolution", "lights", "kernel ms", "old kernel ms",
              "C++ (TBB) ms", "vs C++", "vs old", "list entries");
  for (const auto& size : splitList(a.sizes)) {
    const auto [w, h] = benchutil::sizeOf(size, "--sizes");
    const std::vector<float> depth = benchutil::viewDepth(b, w, h);
    for (const auto& ls : splitList(a.light_counts)) cullCase(b, a, size, depth, ls, records);
  }
  if (!a.frame_sizes.empty()) {
    std::printf("\nFrame breakdown (ms, median of %d; GL passes host-timed on software GL)\n", a.common.reps);
    const std::vector<std::pair<std::string, std::string>> p = {{"tile", std::to_string(a.tile)},
                                                                 {"tile_depth", a.depth_mode}};
    benchutil::runFrameSweep(b, {splitList(a.frame_sizes), splitList(a.frame_lights), a.common.light_density,
                                 {{"tiled-forward", p}, {"tiled-deferred", p}}, a.common.reps, false},
                             records);
  }
  benchutil::writeJson(a.common.json_path, records);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  return ml::benchutil::benchMain("manylights-tiled-bench", [&] { return run(argc, argv); });
}
