#pragma once
// The one interface every light-assignment technique implements (brute force,
// tiled, clustered, hashed). The frame renderer calls, per frame:
//   1. (if needsDepth()) renders depth and hands it over in FrameInputs::depth,
//   2. assign(inputs)       -- builds/updates the structure, on the CL device,
//   3. bindForShading(prog) -- binds the structure's buffers for GLSL,
// and the shared forward/deferred shaders include lookupShader(), which must
// define `struct LightList` (a cursor over the point's list entries),
// `LightList lightListFor(vec3 world_pos, vec3 view_pos, vec2 frag_coord)`,
// `bool listEnded(LightList)` and `bool nextLight(inout LightList, out uint
// light_index)`, which consumes at most one entry and returns whether it names
// a light to evaluate (false past the end, or for an entry the technique
// skips). nextLight must not loop: llvmpipe caps the loop iterations of a
// shader invocation at 65,535 in total, so the shader's one list loop
// visits 32 entries per iteration (gl/shaders/common/shading.glsl). A cursor rather
// than (offset, count) lets a list be stored compressed (clustered shading's
// hit masks).
// Every technique's lists must be conservative: each light whose sphere
// contains the shaded point is in its list (tests hold them to it), which is
// what makes the per-frame lower bound (host/assign/ExactLowerBound.hpp) a
// lower bound of every technique's evaluations.
#include <glm/glm.hpp>

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "host/assign/DebugViewInputs.hpp"
#include "host/assign/ShaderContract.hpp"
#include "host/cl/ClPassTimer.hpp"
#include "host/shared/gpu_types.h"
#include "host/util/PassTimings.hpp"

namespace ml {

class ClRuntime;
class GlPassTimer;
class ShaderProgram;
class SharedBuffer;
struct Camera;

struct FrameInputs {
  ClRuntime& cl;
  const Camera& camera;
  gpu::CameraParams camera_params;  // column-major view/proj, near/far, size
  glm::mat4 view;
  glm::mat4 proj;
  unsigned width = 0;
  unsigned height = 0;
  SharedBuffer& lights;  // gpu::PointLight[light_count]; GL owns it on entry and exit
  const std::vector<gpu::PointLight>& host_lights;  // the same lights, host copy (for host-side builds)
  std::uint32_t light_count = 0;
  bool lights_changed = true;  // positions/radii/count differ from the last frame
  // Window-space depth (float, [0,1], 1 = background), width*height, row 0 at
  // the bottom like gl_FragCoord; null unless needsDepth(). GL owns it on entry.
  SharedBuffer* depth = nullptr;
  ClPassTimer& cl_timer;  // name CL passes with it
  PassTimings& host_timings;  // host-side work (e.g. CPU builds), in ms
  GlPassTimer* gl_timer = nullptr;  // name GL passes with it (uploads), if set
};

class LightAssigner {
 public:
  virtual ~LightAssigner() = default;
  virtual bool needsDepth() const { return false; }
  virtual void assign(const FrameInputs& in) = 0;
  virtual std::string lookupShader() const = 0;  // e.g. "tiled/lookup_tiled.glsl" (under gl/shaders/)
  virtual ShaderDefines shaderDefines() const { return {}; }
  virtual void bindForShading(const ShaderProgram& program) const = 0;
  // Bytes of the light-assignment structures (not the light list itself).
  virtual std::size_t memoryBytes() const { return 0; }
  // Technique-specific figures for reports (e.g. octree layers, unique
  // clusters), as name -> value; printed by `render` and written to JSON.
  virtual std::vector<std::pair<std::string, double>> stats() const { return {}; }
  // A debug view of the last frame that the technique's descriptor lists
  // (TechniqueDescriptor::debug_views, e.g. clustered's "cluster", hashed's
  // "octree-cell"): RGBA floats, width*height, row 0 at the bottom, for
  // writeImage. `frame` holds that frame's depth and unprojection. Only
  // called with a view the descriptor names.
  virtual std::vector<float> debugViewRgba(const std::string& view, const DebugViewInputs& frame) {
    (void)view;
    (void)frame;
    return {};
  }
};

}  // namespace ml
