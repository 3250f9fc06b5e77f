#pragma once
// The seam between the frame and a global-illumination pass: FrameRenderer
// calls a GiPass without knowing which one runs (voxel cone tracing:
// host/vct/VctGiPass) or which light-assignment technique lit the frame.
// Per frame:
//   update(GiSceneInputs)  before the frame's passes: the scene and the frame's
//                          lights (e.g. voxelize, inject, mips);
//   addIndirect(GiFrameInputs) after shading: from the frame's G-buffer
//                          (albedo, octahedral normal, reversed-Z depth; both
//                          pipelines fill it, forward with an extra pass) it
//                          computes the indirect image (indirectRgba()) and adds
//                          it to the shaded image in place.
// Its passes land in the frame's PassTimings. Needs the frame's GL context.
// stats() is everything a front end reports about the pass (render's printout
// and --stats-json fields, bench's records), so no front end needs its type;
// extraImages() are images besides the indirect light (VCT: its ambient
// occlusion), named by the suffixes its descriptor lists (gl/GiDescriptor.hpp);
// view() draws the pass's own data (VCT: the voxel volume) for render's view
// flags and the viewer, from the descriptor's view parameters.
// A pass that keeps work across frames (VctGiPass reuses its voxel volume)
// keys it on lights_version, not on a "changed since the last frame" flag:
// frames rendered without the GI pass (countedRender, the viewer's heat maps)
// would consume such a flag; the version still says whether the lights are
// the ones of the pass's last update.
#include <epoxy/gl.h>

#include <glm/glm.hpp>
#include <nlohmann/json.hpp>

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "gl/GlPassTimer.hpp"
#include "gl/SceneGpu.hpp"
#include "host/assign/TechniqueDescriptor.hpp"
#include "host/shared/gpu_types.h"
#include "host/util/GiUpdateCounts.hpp"
#include "host/util/PassTimings.hpp"

namespace ml {

struct GiSceneInputs {
  const SceneGpu& scene;
  const std::vector<gpu::PointLight>& lights;
  PassTimings& passes;   // the frame's
  // Identifies the light set: FrameRenderer::setLights gives each call a new
  // number, unique in the process (nextLightsVersion()), so equal versions are
  // the same lights whichever renderer set them. 0: unknown, treat as changed.
  std::uint64_t lights_version = 0;
  glm::vec3 eye{0.0f};  // the frame's camera position (VCT's cascade follows it)
};

// A fresh light-set version, never 0 (thread-safe; one counter per process).
inline std::uint64_t nextLightsVersion() {
  static std::atomic<std::uint64_t> last{0};
  return ++last;
}

struct GiFrameInputs {
  glm::mat4 view, proj;
  unsigned width, height;
  GLuint albedo, normal, depth;  // the G-buffer textures (gl/RenderTargets)
  GLuint color;                  // the shaded image (RGBA32F): the indirect light is added to it
  GlPassTimer* timer;            // the frame's GL pass timer
};

// What a GI pass reports about itself after its frames.
struct GiStats {
  std::size_t data_bytes = 0;  // its scene representation (VCT: the voxel volumes): bench's voxel_bytes
  nlohmann::ordered_json json = nlohmann::ordered_json::object();  // render's --stats-json fields, in order
  std::vector<std::string> lines;  // render's printout after the frames, one paragraph each
};

// An image besides the indirect light: <out>_gi_<pass>_<suffix>.png, written as it is.
struct GiImage {
  std::string suffix;
  std::vector<float> rgba;  // linear RGBA, rows bottom-up, the frame's size
};

// What view() draws for: the frame's camera and size.
struct GiViewInputs {
  glm::mat4 view, proj;
  unsigned width, height;
};

// A view of the pass's data: <out>_gi_<pass>_<suffix>.exr (linear) and .png
// (display, also what the viewer shows), and a line render prints.
struct GiViewImage {
  std::string suffix;
  std::vector<float> linear, display;  // RGBA, rows bottom-up
  std::string line;
};

class GiPass {
 public:
  virtual ~GiPass() = default;
  virtual void update(const GiSceneInputs& in) = 0;
  virtual void addIndirect(const GiFrameInputs& in) = 0;
  // The last frame's indirect image, linear RGBA, rows bottom-up: rgb the
  // indirect light, alpha 1 where the pixel sees the scene, 0 where not
  // (the format of host/reference/IndirectReference's image).
  virtual std::vector<float> indirectRgba() const = 0;
  virtual std::size_t memoryBytes() const = 0;
  // Frames whose update() did the scene work, frames that reused the last.
  virtual GiUpdateCounts updateCounts() const = 0;
  virtual GiStats stats() const = 0;
  virtual std::vector<GiImage> extraImages() const { return {}; }
  // `view`: the descriptor's view parameters (defaults, then the given ones,
  // checked); only called for a descriptor with views. Needs the GL context.
  virtual GiViewImage view(const ParamValues& view, const GiViewInputs& in);
};

}  // namespace ml
