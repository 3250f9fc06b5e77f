#pragma once
// `render --gi none|reference|NAME`: global illumination next to the frame.
// reference: the ray-traced one-bounce diffuse indirect image
// (host/reference/IndirectReference.hpp) of the rendered camera frame, written
// as <out stem>_gi_reference.exr (linear float RGBA) and
// <out stem>_gi_reference.png (tone-mapped: c / (c + mean luminance of the
// covered pixels), so the image is legible whatever the lights' intensity),
// its trace time printed and in the stats JSON.
// NAME: a registered GI pass (host/gi/Registry.hpp) adds the indirect light
// to every frame (the frame is direct + indirect), whatever the technique;
// the indirect image alone is written as <out stem>_gi_NAME.exr/.png (the
// same tone-map), its extra images as <out stem>_gi_NAME_<suffix>.png, and
// what it reports (GiPass::stats) is printed and goes into the stats JSON.
// Its parameters are flags generated from its descriptor (--KEY VALUE; a
// switch --KEY or --KEY=on|off), or --gi-param KEY=VALUE; its view
// parameters (e.g. --voxel-view) write <out stem>_gi_NAME_<view>.exr/.png.
// With --gi-reference (a pass whose descriptor names the transport it models)
// the Embree reference of the same transport is traced in the same run (an
// explicit --gi-shadows that differs is refused) and the relative RMSE of the
// indirect image against it reported (gi_rel_rmse).
#include <CLI/CLI.hpp>

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "gl/GiDescriptor.hpp"
#include "host/run/SceneInputs.hpp"
#include "host/cl/ClRuntime.hpp"
#include "host/reference/IndirectReference.hpp"
#include "host/util/ThesisSeed.hpp"

namespace ml {

struct GiArgs {
  std::string mode = "none";       // none | reference | a registered GI pass
  unsigned samples = 64;           // hemisphere samples per pixel
  std::string shadows;             // none | ray: visibility of lights from the secondary hits; empty: giShadows()
  std::uint64_t seed = kThesisSeed;
  unsigned bounces = 1;            // --gi-bounces: of the reference (1..kMaxIndirectBounces)
  SettingList given;               // GI pass parameters given (--KEY, --gi-param KEY=VALUE), in order
  SettingList view;                // GI view parameters given (--voxel-view ...)
  bool with_reference = false;     // --gi-reference
};
inline constexpr unsigned kMaxGiSamples = 1u << 16;

void addGiFlags(CLI::App& cmd, GiArgs& a);
// The reference's --gi-shadows: as given, else the transport the GI pass
// models (its descriptor's reference_shadows), else none.
std::string giShadows(const GiArgs& a);
// Before anything loads: one UserError line naming the flag. `out` is render's
// --out; the GI files are derived from it (none without it).
void checkGiFlags(const GiArgs& a, const std::string& out);
// The descriptor of --gi NAME; null for none and reference.
const GiDescriptor* giPassOf(const GiArgs& a);
// The parameters of --gi NAME's pass (host/gi giParams over its given keys).
ParamValues giPassParams(const GiArgs& a);

// The frame's GI pass for --gi NAME, else none.
std::unique_ptr<GiPass> makeFrameGiPass(const GiArgs& a, ClRuntime& cl, const Scene& scene);

struct GiResult {
  bool ran = false;
  bool has_pass = false;
  double ms = 0;                // reference trace time
  bool has_reference = false;
  bool reference_cached = false;  // read from the reference cache (host/reference/ReferenceCache.hpp)
  IndirectComparison error;     // the pass vs the reference (with --gi-reference), with the reference's noise
  GiStats stats;                // the pass's, after the frames
  std::vector<std::string> files;
};
// After the frames: the reference trace (--gi reference, or a pass with
// --gi-reference), the pass's images and views, the error, the files.
GiResult runGi(const GiArgs& a, const SceneInputs& inputs, const Camera& camera, unsigned width, unsigned height,
               const std::string& out, GiPass* pass);

// "dir/x.png" -> "dir/x_gi_reference.exr" for kind "reference", ext ".exr".
std::string giOutputPath(const std::string& out, const std::string& kind, const std::string& ext);

}  // namespace ml
