#pragma once
// manylights-vct-bench --frame: voxel cone tracing inside the frame, per
// pass, on the Cornell box and the default scene. For each grid edge x
// isotropic/anisotropic x cone count: one VctGiPass in a brute-force deferred
// frame (the technique does not matter to the GI passes), the first frame's
// vct-voxelize, then the median of `reps` frames of every other vct pass, the
// indirect image's relative RMSE against the Embree reference (same run,
// `reference_samples` per pixel, no visibility in the bounce light: the VCT
// transport) and voxel_bytes. Prints one table; returns one JSON record per row.
#include <nlohmann/json.hpp>

#include <string>
#include <vector>

namespace ml::benchvct {

struct FrameSweepOptions {
  std::vector<unsigned> voxels{32, 64, 128};
  std::vector<unsigned> cones{5, 9, 16};
  unsigned levels = 4;
  unsigned width = 320, height = 180;
  int reps = 3;
  unsigned reference_samples = 256;
  std::string device;
};

nlohmann::json frameSweep(const FrameSweepOptions& o);

}  // namespace ml::benchvct
