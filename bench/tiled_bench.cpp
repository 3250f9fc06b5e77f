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
#include <chrono>
#include <cstdio>
#include <fstream>

#include "gl/FrameRenderer.hpp"
#include "gl/GlContext.hpp"
#include "host/app/InputChecks.hpp"
#include "host/app/RenderCommand.hpp"
#include "host/app/SceneInputs.hpp"
#include "host/cl/ClPassTimer.hpp"
#include "host/cl/ClRuntime.hpp"
#include "host/tiled/TileCullerReference.hpp"
#include "host/tiled/TileLightCuller.hpp"
#include "host/tiled/TiledAssigner.hpp"
#include "host/util/Error.hpp"
#include "host/bench/BenchInputs.hpp"
#include "BenchCommon.hpp"

namespace {
using namespace ml;
using benchutil::Clock;
using benchutil::median;
using benchutil::timeMedian;

int run(int argc, char** argv) {
  CLI::App app{"Tile light culling: OpenCL kernel vs multi-threaded C++, and tiled frame breakdowns"};
  std::string json_path, sizes = "320x320,1280x720,1920x1080", light_counts = "1000,10000,100000";
  std::string frame_sizes = "320x320,1280x720", frame_lights = "1000,10000", depth_mode = "minmax";
  unsigned tile = 16;
  int reps = 5;
  float light_density = 0.0f;
  std::string device;
  bool no_legacy = false, passes = false;
  app.add_option("--json", json_path, "write records as JSON");
  app.add_flag("--no-legacy", no_legacy, "skip the previous (per-entry atomics) kernel");
  app.add_flag("--passes", passes, "print the culler's per-pass device times (last repetition)");
  app.add_option("--sizes", sizes, "culling resolutions")->capture_default_str();
  app.add_option("--lights", light_counts, "culling light counts")->capture_default_str();
  app.add_option("--frame-sizes", frame_sizes, "resolutions of the frame breakdowns ('' for none)")->capture_default_str();
  app.add_option("--frame-lights", frame_lights, "light counts of the frame breakdowns")->capture_default_str();
  app.add_option("--light-density", light_density, kLightDensityHelp)->check(finitePositive());
  app.add_option("--tile", tile, "tile size")->capture_default_str();
  app.add_option("--tile-depth", depth_mode, "none|minmax|mask")->capture_default_str();
  app.add_option("--reps", reps, "timed repetitions (median reported)")->capture_default_str();
  app.add_option("--device", device, "OpenCL device");
  CLI11_PARSE(app, argc, argv);
  benchutil::requireWritable("--json", json_path);
  const TileDepthMode mode = parseTileDepthMode(depth_mode);

  auto gl = createHeadlessContext();
  const auto share = gl->shareHandles();
  auto rt = ClRuntime::create(DeviceChoice::resolve(device), &share);
  std::printf("%s\n%s\n", rt->describe().c_str(), gl->describe().c_str());
  SceneInputArgs base;
  base.lights = "1";
  SceneInputs scene = loadSceneInputs(base);
  const Camera& camera = scene.cameras.frames.front();
  nlohmann::ordered_json records = nlohmann::ordered_json::array();

  std::printf("\nTile light culling, tile %u, depth %s (median of %d)\n", tile, depth_mode.c_str(), reps);
  std::printf("%-11s %8s %12s %12s %12s %10s %10s %12s\n", "resolution", "lights", "kernel ms", "old kernel ms",
              "C++ (TBB) ms", "vs C++", "vs old", "list entries");
  for (const auto& size : splitList(sizes)) {
    unsigned w = 0, h = 0;
    parseSize(size, "--sizes", w, h);
    // The depth buffer of the default view at this resolution.
    std::vector<float> depth;
    {
      FrameRenderer r(*rt, scene.scene, w, h);
      r.setLights({});
      TiledAssigner a(*rt, tile, mode);
      r.render(camera, a, {Pipeline::Deferred, false});
      depth = r.targets().readDepth(true);
    }
    const auto cam = camera.params(w, h);
    for (const auto& ls : splitList(light_counts)) {
      SceneInputArgs args;
      args.lights = ls;
      args.light_density = light_density;
      const auto lights = loadSceneInputs(args).lights;
      const auto n = std::uint32_t(lights.size());
      auto& q = rt->queue();
      cl::Buffer lbuf(rt->context(), CL_MEM_READ_ONLY, std::max<std::size_t>(16, n * sizeof(gpu::PointLight)));
      if (n) q.enqueueWriteBuffer(lbuf, CL_TRUE, 0, n * sizeof(gpu::PointLight), lights.data());
      cl::Buffer dbuf(rt->context(), CL_MEM_READ_ONLY, depth.size() * 4);
      q.enqueueWriteBuffer(dbuf, CL_TRUE, 0, depth.size() * 4, depth.data());
      cl::Buffer grid(rt->context(), CL_MEM_READ_WRITE, std::size_t(TileGrid{tile, w, h}.count()) * 8);
      cl::Buffer indices;
      std::size_t cap = 0;
      auto time_culler = [&](TileCullAlgorithm algo, std::uint32_t& total) {
        TileLightCuller culler(*rt, tile, mode, KernelShape::Auto, algo);
        ClPassTimer timer;
        PassTimings pt;
        const double t = timeMedian(reps, [&] {
          pt = PassTimings{};
          total = culler.count(q, lbuf, n, cam, &dbuf, passes ? &timer : nullptr);
          if (std::size_t(total) * 4 > cap) {
            cap = std::max<std::size_t>(16, std::size_t(total) * 4 * 3 / 2);
            indices = cl::Buffer(rt->context(), CL_MEM_READ_WRITE, cap);
          }
          culler.fill(q, lbuf, n, cam, grid, indices, passes ? &timer : nullptr);
          q.finish();
          if (passes) timer.collect(pt);
        });
        if (passes) {
          std::printf("  %s passes:", algo == TileCullAlgorithm::PairAtomics ? "old" : "new");
          for (const auto& [name, ms] : pt.entries()) std::printf(" %s=%.2f", name.c_str(), ms);
          std::printf("\n");
        }
        return t;
      };
      std::uint32_t total = 0, legacy_total = 0;
      const double t_kernel = time_culler(TileCullAlgorithm::ChunkCounts, total);
      const double t_legacy = no_legacy ? 0.0 : time_culler(TileCullAlgorithm::PairAtomics, legacy_total);
      if (!no_legacy && legacy_total != total) throw std::runtime_error("new and old kernels disagree on the list size");
      const TileGrid g{tile, w, h};
      std::size_t ref_total = 0;
      const double t_ref = timeMedian(reps, [&] {
        ref_total = cullTilesReference(lights, depth.data(), cam, g, mode, true).indices.size();
      });
      if (ref_total != total) throw std::runtime_error("kernel and C++ culler disagree on the list size");
      std::printf("%-11s %8u %12.3f %12.3f %12.3f %9.2fx %9.2fx %12u\n", size.c_str(), n, t_kernel * 1e3,
                  t_legacy * 1e3, t_ref * 1e3, t_ref / t_kernel, t_legacy / t_kernel, total);
      std::vector<std::pair<const char*, double>> timed{{"tile_cull_opencl", t_kernel}, {"tile_cull_cpp_tbb", t_ref}};
      if (!no_legacy) timed.emplace_back("tile_cull_opencl_pair_atomics", t_legacy);
      for (auto [name, t] : timed)
        records.push_back({{"name", name}, {"resolution", size}, {"n", n}, {"lights", n}, {"tile", tile},
                           {"depth_mode", depth_mode}, {"seconds", t}, {"items_per_second", n / t},
                           {"bytes_per_second", (depth.size() * 4.0 + n * 32.0) / t}, {"list_entries", total},
                           {"speedup_vs_cpp", t_ref / t_kernel}});
    }
  }

  if (!frame_sizes.empty()) {
    std::printf("\nFrame breakdown (ms, median of %d; GL passes host-timed on software GL)\n", reps);
    for (const auto& size : splitList(frame_sizes)) {
      unsigned w = 0, h = 0;
      parseSize(size, "--frame-sizes", w, h);
      FrameRenderer r(*rt, scene.scene, w, h);
      for (const auto& ls : splitList(frame_lights)) {
        SceneInputArgs args;
        args.lights = ls;
        args.light_density = light_density;
        r.setLights(loadSceneInputs(args).lights);
        for (auto [tech, pipe] : {std::pair{"tiled-forward", Pipeline::Forward}, std::pair{"tiled-deferred", Pipeline::Deferred}}) {
          TiledAssigner a(*rt, tile, mode);
          r.render(camera, a, {pipe, false});
          std::vector<FrameResult> frames;
          for (int i = 0; i < reps; ++i) frames.push_back(r.render(camera, a, {pipe, false}));
          std::printf("%-11s %7s %-15s", size.c_str(), ls.c_str(), tech);
          nlohmann::ordered_json passes;
          for (const auto& [name, ms] : frames.front().passes.entries()) {
            (void)ms;
            std::vector<double> v;
            for (const auto& f : frames) v.push_back(f.passes.get(name));
            const double m = median(v);
            passes[name] = m;
            std::printf(" %s=%.2f", name.c_str(), m);
          }
          std::vector<double> host;
          for (const auto& f : frames) host.push_back(f.host_ms);
          std::printf(" | frame=%.2f\n", median(host));
          records.push_back({{"name", std::string("frame_") + tech}, {"resolution", size}, {"lights", std::stoul(ls)},
                             {"n", std::stoul(ls)}, {"seconds", median(host) * 1e-3},
                             {"items_per_second", double(w) * h / (median(host) * 1e-3)}, {"passes", passes}});
        }
      }
    }
  }
  benchutil::writeJson(json_path, records);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  return ml::benchutil::benchMain("manylights-tiled-bench", [&] { return run(argc, argv); });
}
