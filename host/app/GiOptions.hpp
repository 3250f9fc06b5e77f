#pragma once
// `render --gi none|reference`: global illumination outputs next to the frame.
// reference: the ray-traced one-bounce diffuse indirect image
// (host/reference/IndirectReference.hpp) of the rendered camera frame, written
// as <out stem>_gi_reference.exr (linear float RGBA) and
// <out stem>_gi_reference.png (tone-mapped: c / (c + mean luminance of the
// covered pixels), so the image is legible whatever the lights' intensity),
// its trace time printed and in the stats JSON. `vct` joins later.
#include <CLI/CLI.hpp>

#include <cstdint>
#include <string>
#include <vector>

#include "host/app/SceneInputs.hpp"
#include "host/util/ThesisSeed.hpp"

namespace ml {

struct GiArgs {
  std::string mode = "none";       // none | reference
  unsigned samples = 64;           // hemisphere samples per pixel
  std::string shadows = "none";    // none | ray: visibility of lights from the secondary hits
  std::uint64_t seed = kThesisSeed;
};
inline constexpr unsigned kMaxGiSamples = 1u << 16;

void addGiFlags(CLI::App& cmd, GiArgs& a);
// Before anything loads: one UserError line naming the flag. `out` is render's
// --out; the GI files are derived from it (none without it).
void checkGiFlags(const GiArgs& a, const std::string& out);

struct GiResult {
  bool ran = false;
  double ms = 0;
  std::vector<std::string> files;
};
GiResult runGi(const GiArgs& a, const SceneInputs& inputs, const Camera& camera, unsigned width, unsigned height,
               const std::string& out);

// "dir/x.png" -> "dir/x_gi_reference.exr" for kind "reference", ext ".exr".
std::string giOutputPath(const std::string& out, const std::string& kind, const std::string& ext);

}  // namespace ml
