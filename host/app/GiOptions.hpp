#pragma once
// `render --gi none|reference|vct`: global illumination next to the frame.
// reference: the ray-traced one-bounce diffuse indirect image
// (host/reference/IndirectReference.hpp) of the rendered camera frame, written
// as <out stem>_gi_reference.exr (linear float RGBA) and
// <out stem>_gi_reference.png (tone-mapped: c / (c + mean luminance of the
// covered pixels), so the image is legible whatever the lights' intensity),
// its trace time printed and in the stats JSON.
// vct: voxel cone tracing (host/vct/VctGiPass.hpp) adds the indirect light to
// every frame (the frame is direct + indirect), whatever the technique; the
// indirect image alone is written as <out stem>_gi_vct.exr/.png (the same
// tone-map) and its ambient occlusion as <out stem>_gi_vct_ao.png. With
// --gi-reference the Embree reference of the same transport is traced in the
// same run (--vct-shadows none: no visibility in the bounce light, --gi-shadows
// none; --vct-shadows voxel: --gi-shadows ray; an explicit --gi-shadows that
// differs is refused) and the relative RMSE of the indirect image against it
// reported (gi_rel_rmse).
// --voxel-view albedo|radiance|opacity [--voxel-level k] (with --gi vct): the
// chosen level of the voxel volume seen from the camera as cubes
// (host/vct/VoxelView.hpp), as <out stem>_gi_vct_voxels.exr (linear, alpha 1
// on hit voxels) and .png (radiance with the tone-map above, albedo and
// opacity as they are). With --voxel-slice x|y|z[:position] the view shows
// that plane of the level instead of cubes (host/vct/VoxelSlice.hpp), as
// <out stem>_gi_vct_slice.exr/.png.
#include <CLI/CLI.hpp>

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "gl/GiPass.hpp"
#include "host/app/SceneInputs.hpp"
#include "host/bench/GiSweep.hpp"
#include "host/cl/ClRuntime.hpp"
#include "host/reference/IndirectReference.hpp"
#include "host/util/ThesisSeed.hpp"
#include "host/vct/VctGiPass.hpp"

namespace ml {

struct GiArgs {
  std::string mode = "none";       // none | reference | vct
  unsigned samples = 64;           // hemisphere samples per pixel
  std::string shadows;             // none | ray: visibility of lights from the secondary hits; empty: giShadows()
  std::uint64_t seed = kThesisSeed;
  vct::VctGiSettings vct;          // --voxels --levels --anisotropic --cones --cone-aperture --gi-scale ...
  bool with_reference = false;     // --gi-reference (with --gi vct)
  std::string voxel_view;          // --voxel-view albedo|radiance|opacity (with --gi vct); empty: none
  unsigned voxel_level = 0;        // --voxel-level: the level --voxel-view shows
  std::string voxel_slice;         // --voxel-slice x|y|z[:position]; empty: cubes
};
inline constexpr unsigned kMaxGiSamples = 1u << 16;

void addGiFlags(CLI::App& cmd, GiArgs& a);
// The reference's --gi-shadows: as given, else the transport of --gi vct's
// injection (ray with --vct-shadows voxel), else none.
std::string giShadows(const GiArgs& a);
// Before anything loads: one UserError line naming the flag. `out` is render's
// --out; the GI files are derived from it (none without it).
void checkGiFlags(const GiArgs& a, const std::string& out);

// The frame's GI pass: VCT for --gi vct, else none.
std::unique_ptr<GiPass> makeGiPass(const GiArgs& a, ClRuntime& cl, const Scene& scene);

struct GiResult {
  bool ran = false;
  double ms = 0;                // reference trace time
  bool has_reference = false;
  IndirectError error;          // vct vs the reference (with --gi-reference)
  std::size_t voxel_bytes = 0;  // vct
  // vct: the pipeline's updates and voxelizations over the run's frames
  // (warm-up included): one voxelization, or one per update with --revoxelize;
  // the frames that reused the last volume (lights as at the last update, no
  // --revoxelize): updates + reused = frames with the pass.
  std::size_t vct_updates = 0, vct_voxelizations = 0, vct_reused = 0;
  // vct's hashed lists: full builds, incremental updates, bytes uploaded per update (mean) and the whole image
  std::size_t list_builds = 0, list_updates = 0, list_update_bytes = 0, list_image_bytes = 0;
  std::vector<std::string> files;
};
// After the frames: the reference trace (--gi reference, or vct with
// --gi-reference), the vct pass's images, the error, the files.
GiResult runGi(const GiArgs& a, const SceneInputs& inputs, const Camera& camera, unsigned width, unsigned height,
               const std::string& out, const GiPass* pass);

// `bench --gi vct`: the VCT settings table (host/vct/VctSettingsTable) as the
// GI sweep's descriptor; a point's settings go over the defaults and are
// checked as a whole (UserError: "<flag> key=value,...: <the table's line>").
const GiDescriptor& vctGiDescriptor();

// "dir/x.png" -> "dir/x_gi_reference.exr" for kind "reference", ext ".exr".
std::string giOutputPath(const std::string& out, const std::string& kind, const std::string& ext);

}  // namespace ml
