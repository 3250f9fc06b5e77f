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
#include <epoxy/gl.h>

#include <glm/glm.hpp>

#include <cstddef>
#include <vector>

#include "gl/GlPassTimer.hpp"
#include "gl/SceneGpu.hpp"
#include "host/shared/gpu_types.h"
#include "host/util/PassTimings.hpp"

namespace ml {

struct GiSceneInputs {
  const SceneGpu& scene;
  const std::vector<gpu::PointLight>& lights;
  bool lights_changed;   // since the previous frame
  PassTimings& passes;   // the frame's
};

struct GiFrameInputs {
  glm::mat4 view, proj;
  unsigned width, height;
  GLuint albedo, normal, depth;  // the G-buffer textures (gl/RenderTargets)
  GLuint color;                  // the shaded image (RGBA32F): the indirect light is added to it
  GlPassTimer* timer;            // the frame's GL pass timer
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
};

}  // namespace ml
