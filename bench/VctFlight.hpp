#pragma once
// manylights-vct-bench --flight: voxel cone tracing along a scene's camera
// path (issue 30's flight), the camera-centred cascade against single grids.
// For each scene (the default scene; the thesis suite's Spaceship Indoor,
// its missing mesh skipped as render --allow-missing-meshes does) the path is
// resampled to `frames` cameras and flown once per configuration, rendering
// every camera in order: a single grid of `voxels`^3, the cascade of
// `cascades` levels of `voxels`^3, and a single grid of 2 x `voxels`^3
// (more memory than the cascade); with `fold`, also the cascade with mips
// across its levels (--vct-fold), as a fourth column. At `samples` evenly spaced cameras the
// indirect image is compared with the Embree reference of that camera
// (`reference_samples` per pixel; noise-corrected relative RMSE, as render's
// gi_rel_rmse_corrected). The cascade's camera moves are timed: the GL and CL
// pass times of each frame whose move scrolled a level (vct-voxelize +
// vct-inject + vct-fold + vct-mips + vct-textures) over those of its first frame's full
// build, and the voxels the move redid. Prints a table per scene and a
// summary line; returns one JSON record per scene x sampled camera and one
// summary per scene.
#include <nlohmann/json.hpp>

#include <string>
#include <vector>

namespace ml::benchvct {

struct FlightOptions {
  std::vector<std::string> scenes{"default", "spaceship-indoor"};
  unsigned voxels = 64;
  unsigned cascades = 2;
  bool fold = false;      // a fourth configuration: the cascade with --vct-fold
  unsigned frames = 24;   // the path resampled to this many cameras
  unsigned samples = 6;   // cameras compared with the reference
  unsigned width = 320, height = 180;
  unsigned reference_samples = 256;
  std::string device;
};

nlohmann::json flight(const FlightOptions& o);

}  // namespace ml::benchvct
