// manylights-vct-bench: the compute side of voxel cone tracing on one device,
// peers in the same run.
//  - Mip propagation (isotropic and anisotropic, both kernel shapes) at
//    --edges with --levels: bytes moved per second against an OpenCL copy
//    kernel moving the same bytes (read + write), the bandwidth bound.
//    Bytes moved: every level >= 1 reads its 8 children once per stored
//    value set (isotropic: 1, anisotropic: 6, but level 1 reads isotropic
//    level 0 once) and writes itself.
//  - Injection of --lights lights into a synthetic room (walls one voxel
//    thick, a block in the middle) at --inject-edge: through the hashed
//    structure's lists against brute force over all lights; the mean list
//    length per filled voxel says why. Then with voxel shadows: no shadows,
//    the plain march and the skipping march (its occupancy build apart).
//  - With --frame, instead: cone tracing inside the frame (VctFrameSweep.hpp),
//    per pass at --edges x isotropic/anisotropic x --cones, and the error
//    against the Embree reference, on the Cornell box and the default scene,
//    with their own lights or --frame-lights counts of generated ones, in
//    --frame-technique frames.
//  - With --flight, instead: the camera-centred cascade along each scene's
//    camera path against single grids, error and camera-move cost
//    (VctFlight.hpp).
// Prints tables and, with --json, one record per case.
#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <cstdio>
#include <random>
#include <string>
#include <vector>

#include "MipTraffic.hpp"
#include "host/run/SceneInputs.hpp"
#include "host/cl/ClRuntime.hpp"
#include "host/cl/KernelArgs.hpp"
#include "host/cl/KernelLimits.hpp"
#include "host/compute/HostIo.hpp"
#include "host/hashed/HashedStructure.hpp"
#include "host/scene/LightSet.hpp"
#include "host/techniques/Registry.hpp"
#include "host/util/ThesisSeed.hpp"
#include "host/vct/ConeTracing.hpp"
#include "host/vct/VoxelCascade.hpp"
#include "host/vct/VoxelGrid.hpp"
#include "host/vct/VoxelInjector.hpp"
#include "host/vct/VoxelMips.hpp"
#include "host/vct/VoxelOccupancy.hpp"
#include "BenchCommon.hpp"
#include "BenchSupport.hpp"
#include "VctFlight.hpp"
#include "VctFrameSweep.hpp"

namespace {
using namespace ml;
using benchutil::timeMedian;

// The positive integers of a comma list; UserError naming `flag` otherwise.
std::vector<unsigned> parseCounts(const std::string& list, const char* flag) {
  std::vector<unsigned> out;
  for (const auto& item : splitList(list)) {
    std::size_t used = 0;
    unsigned long v = 0;
    try {
      v = std::stoul(item, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used != item.size() || v == 0 || v > 10000000ul)
      throw UserError(std::string(flag) + ": '" + item + "' is not a count from 1 to 10000000");
    out.push_back(unsigned(v));
  }
  if (out.empty()) throw UserError(std::string(flag) + ": empty list");
  return out;
}

// checkVoxelGrid() names the render command's --voxels; this binary calls the
// grid edge `flag` (--edges, --inject-edge), so its errors say that instead.
void checkGrid(unsigned edge, unsigned levels, const std::string& flag) {
  try {
    vct::checkVoxelGrid({edge, levels, false});
  } catch (const UserError& e) {
    std::string m = e.what();
    for (std::size_t at; (at = m.find("--voxels")) != std::string::npos;) m.replace(at, 8, flag);
    throw UserError(m);
  }
}

constexpr const char* kCopySource =
    "__kernel void copy4(__global const float4* restrict a, __global float4* restrict b, uint n) {\n"
    "  const uint i = get_global_id(0); if (i < n) b[i] = a[i]; }\n";

double mipBytes(unsigned edge, unsigned levels, bool aniso) { return ml::bench::mipTrafficBytes(edge, levels, aniso); }

struct Bench {
  ClRuntime& rt;
  int reps;
  nlohmann::json records = nlohmann::json::array();

  double copySeconds(double bytes) {
    const std::size_t n = std::size_t(bytes / 32);
    cl::Program p(rt.context(), kCopySource, true);
    cl::Kernel k(p, "copy4");
    cl::Buffer a(rt.context(), CL_MEM_READ_WRITE, n * 16), b(rt.context(), CL_MEM_READ_WRITE, n * 16);
    rt.queue().enqueueFillBuffer(a, cl_uint(1), 0, n * 16);
    setArgs(k, a, b, cl_uint(n));
    return timeMedian(reps, [&] {
      rt.queue().enqueueNDRangeKernel(k, cl::NullRange, cl::NDRange((n + 255) / 256 * 256), cl::NDRange(256));
      rt.queue().finish();
    });
  }

  void mips(unsigned edge, unsigned levels) {
    const gpu::VoxelGridParams g{{0, 0, 0, 1}, edge, levels, 0, 0};
    std::vector<gpu::ml_float4> v(gpu::voxel_level_offset(edge, levels), gpu::ml_float4{0.5f, 0.25f, 0.125f, 0.75f});
    cl::Buffer vol = compute::upload(rt.context(), rt.queue(), v);
    cl::Buffer aniso(rt.context(), CL_MEM_READ_WRITE, std::size_t(gpu::voxel_aniso_index(edge, levels, 0, 0)) * 16);
    for (bool an : {false, true}) {
      const double bytes = mipBytes(edge, levels, an), t_copy = copySeconds(bytes);
      for (KernelShape shape : {KernelShape::CpuChunked, KernelShape::GpuWorkGroup}) {
        vct::VoxelMips m(compute::ComputeEnv(rt), compute::Options{.shape = shape});
        const double t = timeMedian(reps, [&] {
          an ? m.anisotropic(rt.queue(), g, vol, aniso) : m.isotropic(rt.queue(), g, vol);
          rt.queue().finish();
        });
        std::printf("%5u^3 %6u %-12s %-5s %10.3f %9.2f %9.2f %8.0f%%\n", edge, levels, an ? "anisotropic" : "isotropic",
                    kernelShapeName(shape), t * 1e3, bytes / t * 1e-9, bytes / t_copy * 1e-9, 100 * t_copy / t);
        records.push_back({{"name", std::string("mips.") + (an ? "anisotropic" : "isotropic")},
                           {"edge", edge}, {"levels", levels}, {"shape", kernelShapeName(shape)}, {"seconds", t},
                           {"bytes", bytes}, {"copy_seconds", t_copy}, {"fraction_of_copy", t_copy / t}});
      }
    }
  }

  // A room: the grid's outer voxel shell plus a centred block, albedo 0.5.
  static std::vector<gpu::VoxelAccum> room(unsigned e, std::size_t& filled) {
    std::vector<gpu::VoxelAccum> a(std::size_t(e) * e * e, gpu::VoxelAccum{});
    filled = 0;
    for (unsigned z = 0; z < e; ++z)
      for (unsigned y = 0; y < e; ++y)
        for (unsigned x = 0; x < e; ++x) {
          const bool wall = x == 0 || y == 0 || z == 0 || x == e - 1 || y == e - 1 || z == e - 1;
          const auto in = [&](unsigned c) { return c >= 3 * e / 8 && c < 5 * e / 8; };
          if (!wall && !(in(x) && in(y) && in(z))) continue;
          const int ny = y == 0 ? 1024 : (y == e - 1 ? -1024 : 0), nx = x == 0 ? 1024 : (x == e - 1 ? -1024 : 0);
          a[x + e * (y + std::size_t(e) * z)] = {{128, 128, 128, 1}, {nx, ny, ny || nx ? 0 : 1024, 0}};
          ++filled;
        }
    return a;
  }

  // The room at `edge` with `n_lights` random lights of `radius`, uploaded.
  struct InjectInputs {
    gpu::VoxelGridParams g;
    std::vector<gpu::VoxelAccum> accum;
    std::size_t filled = 0;
    std::vector<gpu::PointLight> lights;
    cl::Buffer ab, lb, out;
  };
  InjectInputs injectInputs(unsigned edge, std::size_t n_lights, double radius) {
    InjectInputs in;
    in.g = gpu::VoxelGridParams{{0, 0, 0, 1.0f / float(edge)}, edge, 1, 0, 0};
    in.accum = room(edge, in.filled);
    std::mt19937_64 rng(kThesisSeed + n_lights);
    std::uniform_real_distribution<float> u(0.02f, 0.98f);
    for (std::size_t i = 0; i < n_lights; ++i)
      in.lights.push_back(makeLight({u(rng), u(rng), u(rng)}, float(radius), glm::vec3(u(rng), u(rng), u(rng))));
    in.ab = compute::upload(rt.context(), rt.queue(), in.accum);
    in.lb = compute::upload(rt.context(), rt.queue(), in.lights);
    in.out = cl::Buffer(rt.context(), CL_MEM_READ_WRITE, in.accum.size() * 16);
    return in;
  }

  void inject(unsigned edge, std::size_t n_lights, double radius) {
    InjectInputs in = injectInputs(edge, n_lights, radius);
    const gpu::VoxelGridParams& g = in.g;
    const auto& accum = in.accum;
    const auto& lights = in.lights;
    const std::size_t filled = in.filled;
    auto& q = rt.queue();
    cl::Buffer &ab = in.ab, &lb = in.lb, &out = in.out;
    hashed::HashedStructure hs{hashed::HashedConfig{}};
    hs.build(lights);
    const compute::ComputeEnv env(rt);
    vct::HashedListsCl lists(env);
    lists.upload(q, hs.linkless(), true);
    double entries = 0;  // list entries the hashed kernel walks
    for (std::size_t i = 0; i < accum.size(); ++i)
      if (accum[i].albedo_count[3]) {
        const float s = g.origin_voxel_size.w;
        const glm::vec3 p((float(i % edge) + 0.5f) * s, (float(i / edge % edge) + 0.5f) * s, (float(i / edge / edge) + 0.5f) * s);
        entries += hs.linkless().lookup(p).count;
      }
    vct::VoxelInjector inj(env);
    const double t_brute = timeMedian(reps, [&] { inj.brute(q, g, ab, lb, lights.size(), out); q.finish(); });
    const double t_hashed = timeMedian(reps, [&] { inj.hashed(q, g, ab, lb, lights.size(), lists, out); q.finish(); });
    std::printf("%5u^3 %8zu %7zu %6.3f %10.1f %12.3f %12.3f %8.1fx %12.1f\n", edge, n_lights, filled, radius,
                hs.lastBuild().total_ms, t_brute * 1e3, t_hashed * 1e3, t_brute / t_hashed, entries / double(filled));
    records.push_back({{"name", "inject"}, {"edge", edge}, {"lights", n_lights}, {"radius", radius},
                       {"filled_voxels", filled}, {"brute_seconds", t_brute}, {"hashed_seconds", t_hashed},
                       {"speedup", t_brute / t_hashed}, {"hashed_build_ms", hs.lastBuild().total_ms},
                       {"mean_list_entries", entries / double(filled)}, {"shape", kernelShapeName(inj.tuning().shape)}});
  }

  // Hashed injection with voxel shadows against none: the plain march (every
  // sample loads its voxel) and the skipping one (occupancy hierarchy built
  // once, as after a voxelization, its build timed apart), same inputs.
  void shadows(unsigned edge, std::size_t n_lights, double radius) {
    InjectInputs in = injectInputs(edge, n_lights, radius);
    auto& q = rt.queue();
    hashed::HashedStructure hs{hashed::HashedConfig{}};
    hs.build(in.lights);
    const compute::ComputeEnv env(rt);
    vct::HashedListsCl lists(env);
    lists.upload(q, hs.linkless(), true);
    vct::VoxelInjector none(env), plain(env, {}, true, false), skipping(env, {}, true);
    vct::VoxelOccupancy occ(env);
    const double t_occ = timeMedian(reps, [&] { occ.build(q, in.g.edge, in.ab); q.finish(); });
    const auto time = [&](vct::VoxelInjector& inj) {
      return timeMedian(reps, [&] { inj.hashed(q, in.g, in.ab, in.lb, in.lights.size(), lists, in.out, nullptr, &occ); q.finish(); });
    };
    const double t_none = time(none), t_plain = time(plain), t_skip = time(skipping);
    std::printf("%5u^3 %8zu %6.3f %10.3f %12.3f %12.3f %9.2f %12.3f %9.2f\n", edge, n_lights, radius, t_none * 1e3,
                t_plain * 1e3, t_skip * 1e3, t_skip / t_none, t_occ * 1e3, t_plain / t_skip);
    records.push_back({{"name", "inject.shadows"}, {"edge", edge}, {"lights", n_lights}, {"radius", radius},
                       {"filled_voxels", in.filled}, {"none_seconds", t_none}, {"plain_march_seconds", t_plain},
                       {"skipping_march_seconds", t_skip}, {"occupancy_seconds", t_occ},
                       {"shadowed_over_none", t_skip / t_none}, {"plain_over_skipping", t_plain / t_skip},
                       {"shape", kernelShapeName(skipping.tuning().shape)}});
  }
};

struct Args {
  benchutil::BenchArgs common;  // --json, --reps, --device (no --light-density here)
  std::string edges = "32,64,128", light_counts = "1000,10000";
  unsigned levels = 4, inject_edge = 64;
  double radius = 0.1;
  bool frame = false;
  std::string cones = "5,9,16", frame_lights, frame_technique = "deferred";
  bool flight = false;
  std::string flight_scenes = "default,spaceship-indoor";
  unsigned flight_voxels = 64, flight_cascades = 2, flight_frames = 24, flight_samples = 6;
  bool flight_fold = false;
};

void parseArgs(CLI::App& app, Args& a) {
  app.add_flag("--frame", a.frame, "cone tracing in the frame instead: per pass and error vs the reference");
  app.add_option("--cones", a.cones, "--frame: diffuse cone counts")->capture_default_str();
  app.add_option("--frame-lights", a.frame_lights,
                 "--frame: generated light counts (as render --lights N), e.g. 1000,10000; default: each scene's own");
  app.add_option("--frame-technique", a.frame_technique, "--frame: the technique of the direct light")
      ->capture_default_str();
  app.add_flag("--flight", a.flight,
               "fly each scene's camera path instead: the cascade against single grids (error, camera-move cost)");
  app.add_option("--flight-scenes", a.flight_scenes, "--flight: default and/or thesis-suite scene names")
      ->capture_default_str();
  app.add_option("--flight-voxels", a.flight_voxels, "--flight: voxels per level")->capture_default_str();
  app.add_option("--flight-cascades", a.flight_cascades, "--flight: cascade levels")->capture_default_str();
  app.add_flag("--flight-fold", a.flight_fold, "--flight: also the cascade with mips across its levels (--vct-fold)");
  app.add_option("--flight-frames", a.flight_frames, "--flight: the path resampled to this many cameras")
      ->capture_default_str();
  app.add_option("--flight-samples", a.flight_samples, "--flight: cameras compared with the reference")
      ->capture_default_str();
  app.add_option("--json", a.common.json_path, "write records as JSON");
  app.add_option("--edges", a.edges, "mip grid edges (powers of two)")->capture_default_str();
  app.add_option("--levels", a.levels, "mip levels (--frame: default auto, log2(edge) - 1 per edge)")
      ->capture_default_str();
  app.add_option("--lights", a.light_counts, "injection light counts")->capture_default_str();
  app.add_option("--inject-edge", a.inject_edge, "injection grid edge")->capture_default_str();
  app.add_option("--radius", a.radius, "light radius, as a fraction of the room")->capture_default_str();
  app.add_option("--reps", a.common.reps, "timed repetitions (median reported)")->capture_default_str();
  app.add_option("--device", a.common.device, "OpenCL device");
}

// The flags parsing leaves unchecked, checked before CL opens.
void checkArgs(const Args& a) {
  if (a.common.reps < 1) throw UserError("--reps: must be at least 1");
  if (!(a.radius > 0)) throw UserError("--radius: must be positive");
  if (a.flight_frames < 2) throw UserError("--flight-frames: must be at least 2 (a flight moves the camera)");
  if (a.flight_samples < 1) throw UserError("--flight-samples: must be at least 1");
  if (a.flight_cascades < 1 || a.flight_cascades > vct::kMaxCascades)
    throw UserError("--flight-cascades: must be 1.." + std::to_string(vct::kMaxCascades));
  if (a.flight_fold && a.flight_cascades < 2) throw UserError("--flight-fold: needs --flight-cascades 2 or more");
}

int run(int argc, char** argv) {
  CLI::App app{"Voxel cone tracing, compute side: mip bandwidth vs copy, hashed vs brute-force injection"};
  Args a;
  parseArgs(app, a);
  if (const auto stop = benchutil::parseCommandLine(app, argc, argv, a.common, [&] { checkArgs(a); })) return *stop;
  const std::vector<unsigned> edge_list = parseCounts(a.edges, "--edges");
  const std::vector<unsigned> light_list = parseCounts(a.light_counts, "--lights");
  for (unsigned e : edge_list) checkGrid(e, a.levels, "--edges");
  if (a.frame) {
    benchvct::FrameSweepOptions o;
    o.voxels = edge_list;
    o.cones = parseCounts(a.cones, "--cones");
    for (unsigned c : o.cones) vct::checkConeSettings(c, 45.0f);
    if (!a.frame_lights.empty()) o.lights = parseCounts(a.frame_lights, "--frame-lights");
    o.technique = findTechnique(a.frame_technique, "--frame-technique").name;
    o.levels = app.count("--levels") ? a.levels : 0;
    o.reps = a.common.reps;
    o.device = a.common.device;
    benchutil::writeJson(a.common.json_path, benchvct::frameSweep(o));
    return 0;
  }
  if (a.flight) {
    benchvct::FlightOptions o;
    o.scenes = splitList(a.flight_scenes);
    checkGrid(a.flight_voxels, 1, "--flight-voxels");
    o.voxels = a.flight_voxels;
    o.cascades = a.flight_cascades;
    o.fold = a.flight_fold;
    o.frames = a.flight_frames;
    o.samples = a.flight_samples;
    o.device = a.common.device;
    benchutil::writeJson(a.common.json_path, benchvct::flight(o));
    return 0;
  }
  checkGrid(a.inject_edge, 1, "--inject-edge");
  auto rt = ClRuntime::create(DeviceChoice::resolve(a.common.device));
  std::printf("%s\n", rt->describe().c_str());
  Bench b{*rt, a.common.reps};
  std::printf("\nMip propagation, all levels (median of %d); GB/s = bytes read + written per second\n", a.common.reps);
  std::printf("%7s %6s %-12s %-5s %10s %9s %9s %9s\n", "grid", "levels", "filter", "shape", "ms", "GB/s", "copy GB/s",
              "of copy");
  for (unsigned e : edge_list) b.mips(e, a.levels);
  std::printf("\nInjection (median of %d): hashed lists vs brute force, room of %u^3 voxels\n", a.common.reps,
              a.inject_edge);
  std::printf("%7s %8s %7s %6s %10s %12s %12s %9s %12s\n", "grid", "lights", "filled", "radius", "build ms",
              "brute ms", "hashed ms", "speedup", "list/voxel");
  for (unsigned n : light_list) b.inject(a.inject_edge, n, a.radius);
  std::printf("\nInjection with voxel shadows (hashed, median of %d), room of %u^3 voxels: none, plain march, "
              "skipping march\n", a.common.reps, a.inject_edge);
  std::printf("%7s %8s %6s %10s %12s %12s %9s %12s %9s\n", "grid", "lights", "radius", "none ms", "plain ms",
              "skipping ms", "vs none", "occupancy ms", "speedup");
  for (unsigned n : light_list) b.shadows(a.inject_edge, n, a.radius);
  benchutil::writeJson(a.common.json_path, b.records);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  return ml::benchutil::benchMain("manylights-vct-bench", [&] { return run(argc, argv); });
}
