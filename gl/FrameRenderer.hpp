#pragma once
// Renders frames of one scene at one resolution with any LightAssigner, in a
// forward or deferred pipeline. Data flow per frame:
//   forward : [depth pre-pass -> depth export] -> assign (CL) -> forward shading
//   deferred: G-buffer -> [depth export] -> assign (CL) -> full-screen shading
// The bracketed steps run only when the assigner needsDepth(). Lights live in a
// SharedBuffer that both the kernels and the shaders read.
// With FrameOptions::gi (gl/GiPass.hpp) the frame also runs, whatever the
// technique: gi->update() first, a G-buffer pass in forward (`gi-gbuffer`: the
// GI pass reads albedo, normal and depth, which only deferred has), and
// gi->addIndirect() after shading, which adds the indirect light in place.
#include <chrono>
#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "gl/GiPass.hpp"
#include "gl/GlPassTimer.hpp"
#include "gl/RenderTargets.hpp"
#include "gl/SceneGpu.hpp"
#include "gl/ShaderProgram.hpp"
#include "gl/SharedBuffer.hpp"
#include "host/assign/ExactLowerBound.hpp"
#include "host/assign/LightAssigner.hpp"
#include "host/cl/ClPassTimer.hpp"
#include "host/scene/Camera.hpp"
#include "host/scene/Scene.hpp"

namespace ml {

struct FrameOptions {
  Pipeline pipeline = Pipeline::Forward;
  // Count light evaluations per pixel, and compute the exact lower bound
  // (host/assign/ExactLowerBound.hpp) from the frame's depth. Costs shading
  // time and a CL pass; timings of counted frames are not comparable.
  bool count_lights = false;
  // false (--no-shading): depth and light assignment only, so that the
  // assignment's cost is measured without the shading pass (on llvmpipe the
  // larger part of a many-light frame). Counting then yields the exact lower
  // bound and covered pixels (a depth pre-pass runs for it if the technique
  // has none) but no light evaluations.
  bool shade = true;
  // Global illumination added to the shaded image (not owned; none: direct
  // light only). Skipped without shading.
  GiPass* gi = nullptr;
};

struct FrameResult {
  PassTimings passes;  // GL and CL passes, ms
  double host_ms = 0;  // wall time of the whole frame on the host (submit..finish)
  // With count_lights:
  std::uint64_t light_evaluations = 0;     // sum over pixels of lights evaluated for the visible surface
  std::uint64_t lower_bound = 0;           // sum over pixels of lights whose sphere contains the surface point
  // Sum over pixels of the bound's lights that the shader did not evaluate
  // (the pixel's bound minus its evaluated lights in range): 0 unless a
  // technique's list or the shader's loop dropped a light.
  std::uint64_t missed_lights = 0;
  std::uint64_t fragment_evaluations = 0;  // over every shaded fragment, overdraw included
  std::uint64_t covered_pixels = 0;
  std::size_t memory_bytes = 0;            // assigner structures
  bool shaded = true;                      // false: FrameOptions::shade was off (no evaluations counted)
};

class FrameRenderer {
 public:
  FrameRenderer(ClRuntime& cl, const Scene& scene, unsigned width, unsigned height);
  ~FrameRenderer();

  void setLights(const std::vector<gpu::PointLight>& lights);
  FrameResult render(const Camera& camera, LightAssigner& assigner, const FrameOptions& options);

  const RenderTargets& targets() const { return *targets_; }
  unsigned width() const { return width_; }
  unsigned height() const { return height_; }
  std::uint32_t lightCount() const { return light_count_; }

 private:
  const ShaderProgram& program(const std::string& kind, const LightAssigner& a, bool count);
  void beginFrame(bool count);
  void depthPasses(bool deferred, const FrameOptions& options, const glm::mat4& view, const glm::mat4& proj,
                   LightAssigner& assigner);
  void gbufferPass(const char* name, const glm::mat4& view, const glm::mat4& proj, LightAssigner& assigner);
  void assignLights(const Camera& camera, const glm::mat4& view, const glm::mat4& proj, LightAssigner& assigner,
                    FrameResult& result);
  void finishFrame(std::chrono::steady_clock::time_point t0, const LightAssigner& assigner, FrameResult& result);
  void exportDepth();
  void shadeOnlyFirstEqualFragment();
  void readDepthInto(bool deferred);
  void shade(bool deferred, bool count, const glm::mat4& view, const glm::mat4& proj, LightAssigner& assigner);
  void countLights(bool deferred, const glm::mat4& view, const glm::mat4& proj, FrameResult& result);
  void setFrameUniforms(const ShaderProgram& p, const glm::mat4& view, const glm::mat4& proj) const;

  ClRuntime& cl_;
  unsigned width_, height_;
  std::unique_ptr<SceneGpu> scene_;
  std::unique_ptr<RenderTargets> targets_;
  std::unique_ptr<SharedBuffer> lights_;
  std::unique_ptr<SharedBuffer> depth_;
  GLuint stats_ssbo_ = 0;
  GLuint empty_vao_ = 0;
  std::uint32_t light_count_ = 0;
  Pipeline pipeline_ = Pipeline::Forward;  // of the frame being rendered
  std::vector<gpu::PointLight> host_lights_;
  bool lights_changed_ = true;
  std::uint64_t lights_version_ = 0;  // GiSceneInputs::lights_version, set by setLights
  std::unique_ptr<ExactLowerBound> bound_;  // created by the first counted frame
  bool bound_lights_stale_ = true;
  cl::Buffer bound_counts_;                 // uint per pixel
  std::map<std::string, ShaderProgram> programs_;
  GlPassTimer gl_timer_;
  ClPassTimer cl_timer_;
};

}  // namespace ml
