#include "VctFrameSweep.hpp"

#include <cstdio>

#include "host/run/SceneInputs.hpp"
#include "host/run/RunLayer.hpp"
#include "host/reference/IndirectReference.hpp"
#include "host/techniques/Registry.hpp"
#include "host/util/DataPaths.hpp"
#include "host/util/ThesisSeed.hpp"
#include "host/vct/VctGiPass.hpp"

namespace ml::benchvct {
namespace {

constexpr const char* kPasses[] = {"vct-lists", "vct-inject", "vct-mips", "vct-textures", "vct-trace", "vct-upsample"};

struct SweepScene {
  std::string name;
  SceneInputs in;
  IndirectImage reference;  // with its noise estimate
};

// `lights` > 0: that many lights generated as `render --lights N` does; 0: the scene's own set.
SweepScene loadScene(const std::string& name, unsigned lights, const FrameSweepOptions& o) {
  SceneInputArgs a;
  if (name == "cornell") {
    const std::string dir = dataPath("cornell") + "/";
    a.scene = dir + "cornell.gltf";
    a.lights = dir + "lights.json";
    a.camera = dir + "camera.json";
  }
  if (lights > 0) a.lights = std::to_string(lights);
  SweepScene s{name, loadSceneInputs(a), {}};
  const IndirectOptions r{o.reference_samples, kThesisSeed, false};
  s.reference = traceIndirectReference(s.in.scene, s.in.lights, s.in.cameras.frames.front(), o.width, o.height, r);
  return s;
}

nlohmann::json row(RunContext& ctx, FrameRenderer& renderer, const SweepScene& s, const vct::VctGiSettings& v,
                   const FrameSweepOptions& o) {
  auto assigner = makeAssigner(o.technique, *ctx.cl, &s.in.scene);
  vct::VctGiPass gi(*ctx.cl, v, s.in.scene.bounds);
  const FrameOptions options{findTechnique(o.technique).pipeline, false, true, &gi};
  const Camera& cam = s.in.cameras.frames.front();
  const double voxelize = renderer.render(cam, *assigner, options).passes.get("vct-voxelize");
  // The lights are given again before each timed frame: a new light set to
  // the pass, so every timed frame updates the volume (lists, inject, mips,
  // textures) as with moving lights; with static lights it would reuse it.
  const TimedFrame t = timedRenders(renderer, *assigner, options, cam, static_cast<unsigned>(o.reps),
                                    [&] { renderer.setLights(s.in.lights); });
  const IndirectComparison c = compareWithReference(gi.indirectRgba(), s.reference);
  const IndirectError& e = c.error;
  nlohmann::json j{{"scene", s.name},         {"lights", s.in.lights.size()}, {"voxels", v.grid.voxels},
                   {"levels", v.grid.levels}, {"anisotropic", v.grid.anisotropic}, {"cones", v.cones},
                   {"vct-voxelize", voxelize}, {"gi_rel_rmse", e.rel_rmse}, {"gi_ref_noise", c.ref_noise},
                   {"gi_rel_rmse_corrected", c.corrected}, {"voxel_bytes", vct::voxelBytes(v.grid)},
                   {"vct_updates", gi.volumeUpdates()}};
  double sum = voxelize;
  std::printf("%-8s %7zu %5u^3 %-5s %5u %9.2f", s.name.c_str(), s.in.lights.size(), v.grid.voxels,
              v.grid.anisotropic ? "aniso" : "iso", v.cones, voxelize);
  for (const char* p : kPasses) {
    const double ms = t.passes.get(p);  // NaN where the device could not time it: null in JSON, n/a here
    j[p] = PassTimings::isMissing(ms) ? nlohmann::json() : nlohmann::json(ms);
    sum += ms;
    std::printf(" %9s", passTimeText(ms, 2).c_str());
  }
  std::printf(" %9s %8.4f %9.4f %9.1f\n", passTimeText(sum, 2).c_str(), e.rel_rmse, c.corrected,
              double(vct::voxelBytes(v.grid)) / 1e6);
  return j;
}

}  // namespace

nlohmann::json frameSweep(const FrameSweepOptions& o) {
  RunContext ctx = RunContext::open(DeviceChoice::resolve(o.device));
  ctx.printDevices();
  std::printf("\nVCT in %s frames, %ux%u (trace at 0.5), ms: vct-voxelize of the first frame, the rest median of %d "
              "frames, each updating the volume (the lights set again, as if they moved); rel RMSE vs the Embree "
              "reference (%u samples/pixel) and without the reference's own noise (corrected)\n",
              o.technique.c_str(), o.width, o.height, o.reps, o.reference_samples);
  std::printf("%-8s %7s %7s %-5s %5s %9s", "scene", "lights", "voxels", "vol", "cones", "voxelize");
  for (const char* p : kPasses) std::printf(" %9s", p + 4);
  std::printf(" %9s %8s %9s %9s\n", "sum", "rel RMSE", "corrected", "MB");
  nlohmann::json records = nlohmann::json::array();
  const std::vector<unsigned> light_sets = o.lights.empty() ? std::vector<unsigned>{0} : o.lights;
  for (const char* name : {"cornell", "default"})
    for (unsigned lights : light_sets) {
      const SweepScene s = loadScene(name, lights, o);
      FrameRenderer renderer(*ctx.cl, s.in.scene, o.width, o.height);
      renderer.setLights(s.in.lights);
      for (unsigned voxels : o.voxels)
        for (bool aniso : {false, true})
          for (unsigned cones : o.cones) {
            vct::VctGiSettings v;
            v.grid = {voxels, o.levels ? o.levels : vct::autoLevels(voxels), aniso};
            v.cones = cones;
            records.push_back(row(ctx, renderer, s, v, o));
          }
    }
  return records;
}

}  // namespace ml::benchvct
