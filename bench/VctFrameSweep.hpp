#pragma once
// manylights-vct-bench --frame: voxel cone tracing inside the frame, per
// pass, on the Cornell box and the default scene, each with its own light set
// or, with `lights`, with each of those counts generated as `render --lights N`
// generates them (BenchInputs.hpp: seeded, in the scene's light volumes with
// their radius, data/default/light_volumes.json; the Cornell box has none, so
// uniform in its bounds with radius 1/20 of their largest side). For each
// light set x grid edge x isotropic/anisotropic x cone count: one VctGiPass
// in a frame of `technique` (brute-force deferred by default; the technique
// does not matter to the GI passes, only to the frame's time), the first frame's
// vct-voxelize, then the median of `reps` frames of every other vct pass, the
// indirect image's relative RMSE against the Embree reference (same run,
// `reference_samples` per pixel, no visibility in the bounce light: the VCT
// transport) and voxel_bytes. Prints one table; returns one JSON record per row
// (with its light count, `lights`).
#include <nlohmann/json.hpp>

#include <string>
#include <vector>

namespace ml::benchvct {

struct FrameSweepOptions {
  std::vector<unsigned> voxels{32, 64, 128};
  std::vector<unsigned> cones{5, 9, 16};
  std::vector<unsigned> lights;  // generated light counts; empty: each scene's own lights
  std::string technique = "deferred";
  unsigned levels = 0;  // 0: vct::autoLevels(voxels), as render --levels auto
  unsigned width = 320, height = 180;
  int reps = 3;
  unsigned reference_samples = 256;
  std::string device;
};

nlohmann::json frameSweep(const FrameSweepOptions& o);

}  // namespace ml::benchvct
