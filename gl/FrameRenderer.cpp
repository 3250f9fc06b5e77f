#include "gl/FrameRenderer.hpp"

#include <chrono>
#include <stdexcept>

#include "gl/GlCheck.hpp"
#include "gl/ViewUniforms.hpp"
#include "host/cl/ClRuntime.hpp"
#include "host/shared/shading_bindings.h"

namespace ml {

FrameRenderer::FrameRenderer(ClRuntime& cl, const Scene& scene, unsigned width, unsigned height)
    : cl_(cl), width_(width), height_(height) {
  scene_ = std::make_unique<SceneGpu>(scene);
  targets_ = std::make_unique<RenderTargets>(width, height);
  lights_ = std::make_unique<SharedBuffer>(cl, 1024 * sizeof(gpu::PointLight), "lights");
  depth_ = std::make_unique<SharedBuffer>(cl, static_cast<size_t>(width) * height * sizeof(float), "depth");
  glCreateBuffers(1, &stats_ssbo_);
  glNamedBufferStorage(stats_ssbo_, 16, nullptr, GL_DYNAMIC_STORAGE_BIT);
  glCreateVertexArrays(1, &empty_vao_);
  glCheck("creating the frame renderer");
}

FrameRenderer::~FrameRenderer() {
  programs_.clear();
  glDeleteBuffers(1, &stats_ssbo_);
  glDeleteVertexArrays(1, &empty_vao_);
}

void FrameRenderer::setLights(const std::vector<gpu::PointLight>& lights) {
  lights_->reserve(lights.size() * sizeof(gpu::PointLight));
  lights_->upload(lights.data(), lights.size() * sizeof(gpu::PointLight));
  light_count_ = static_cast<std::uint32_t>(lights.size());
  host_lights_ = lights;
  lights_changed_ = true;
  lights_version_ = nextLightsVersion();
  bound_lights_stale_ = true;
}

const ShaderProgram& FrameRenderer::program(const std::string& kind, const LightAssigner& a, bool count) {
  const std::string key = kind + "|" + a.lookupShader() + "|" + (count ? "count" : "") + [&] {
    std::string d;
    for (const auto& [k, v] : a.shaderDefines()) d += "|" + k + "=" + v;
    return d;
  }();
  if (auto it = programs_.find(key); it != programs_.end()) return it->second;
  ShaderDefines defines = a.shaderDefines();
  if (count) defines.emplace_back("COUNT_LIGHTS", "1");
  const ShaderAliases aliases = {{"lookup.glsl", a.lookupShader()}};
  std::vector<std::string> files;
  if (kind == "depth") files = {"common/geometry.vert", "common/depth_only.frag"};
  else if (kind == "forward") files = {"common/geometry.vert", "common/forward.frag"};
  else if (kind == "gbuffer") files = {"common/geometry.vert", "common/gbuffer.frag"};
  else if (kind == "deferred") files = {"common/fullscreen.vert", "common/deferred.frag"};
  else throw std::logic_error("FrameRenderer: unknown shader kind '" + kind + "'");
  auto [it, ok] = programs_.emplace(key, ShaderProgram(files, defines, aliases));
  (void)ok;
  return it->second;
}

void FrameRenderer::setFrameUniforms(const ShaderProgram& p, const glm::mat4& view, const glm::mat4& proj) const {
  setViewUniforms(p, view, proj, width_, height_);
  p.set("u_light_count", light_count_);
}

void FrameRenderer::shadeOnlyFirstEqualFragment() {
  // Depth EQUAL against the pre-pass passes every fragment whose depth ties
  // with the visible one (coplanar faces, or faces that round to the same
  // float near their intersection), and the last one drawn would be shaded.
  // A single GL_GREATER pass keeps the first of them, as the G-buffer does;
  // the stencil keeps it here too: the first fragment to pass marks the pixel.
  glDepthFunc(GL_EQUAL);
  glDepthMask(GL_FALSE);
  const GLint zero = 0;
  glClearNamedFramebufferiv(targets_->outputFbo(), GL_STENCIL, 0, &zero);
  glEnable(GL_STENCIL_TEST);
  glStencilMask(0xff);
  glStencilFunc(GL_EQUAL, 0, 0xff);
  glStencilOp(GL_KEEP, GL_KEEP, GL_INCR);
}

void FrameRenderer::exportDepth() {
  // The depth image reaches the kernels as a buffer: a pack-buffer read is a
  // GPU-side copy on real GPUs and a plain memcpy into the shared (mapped)
  // storage on llvmpipe. Deferred's depth is the G-buffer's, forward's the pre-pass's.
  GlPassScope scope(&gl_timer_, "depth-export");
  readDepthInto(pipeline_ == Pipeline::Deferred);
}

void FrameRenderer::readDepthInto(bool deferred) {
  glBindFramebuffer(GL_READ_FRAMEBUFFER, deferred ? targets_->gbufferFbo() : targets_->outputFbo());
  glBindBuffer(GL_PIXEL_PACK_BUFFER, depth_->gl());
  glPixelStorei(GL_PACK_ALIGNMENT, 4);
  glReadPixels(0, 0, static_cast<GLsizei>(width_), static_cast<GLsizei>(height_), GL_DEPTH_COMPONENT, GL_FLOAT,
               nullptr);
  glBindBuffer(GL_PIXEL_PACK_BUFFER, 0);
  glBindFramebuffer(GL_READ_FRAMEBUFFER, 0);
  glCheck("exporting depth to the shared buffer");
}

FrameResult FrameRenderer::render(const Camera& camera, LightAssigner& assigner, const FrameOptions& options) {
  // Cameras from files were checked naming the file; this catches the rest.
  checkDepthRange(camera, "camera");
  const auto t0 = std::chrono::steady_clock::now();
  FrameResult result;
  result.shaded = options.shade;
  pipeline_ = options.pipeline;
  const bool deferred = options.pipeline == Pipeline::Deferred;
  GiPass* gi = options.shade ? options.gi : nullptr;
  const float aspect = static_cast<float>(width_) / static_cast<float>(height_);
  const glm::mat4 view = camera.view();
  const glm::mat4 proj = camera.projection(aspect);

  // 0. The GI pass's own update (its GL passes set their own state, so it goes first).
  if (gi) gi->update({*scene_, host_lights_, result.passes, lights_version_, camera.eye});
  beginFrame(options.count_lights);
  // 1. Depth: G-buffer (deferred, or forward with GI) and the pre-pass (forward, if needed).
  depthPasses(deferred, options, view, proj, assigner);
  if (assigner.needsDepth()) exportDepth();
  // 2. Light assignment on the CL device.
  assignLights(camera, view, proj, assigner, result);
  // 3. Shading, then 4. the indirect light added to it.
  if (options.shade) shade(deferred, options.count_lights, view, proj, assigner);
  if (gi)
    gi->addIndirect({view, proj, width_, height_, targets_->albedoTexture(), targets_->normalTexture(),
                     targets_->gbufferDepthTexture(), targets_->outputColorTexture(), &gl_timer_});
  finishFrame(t0, assigner, result);
  if (options.count_lights) countLights(deferred, view, proj, result);
  return result;
}

void FrameRenderer::beginFrame(bool count) {
  glViewport(0, 0, static_cast<GLsizei>(width_), static_cast<GLsizei>(height_));
  // Reversed-Z (host/shared/depth_convention.h): [0, 1] clip depth, cleared
  // to kSkyDepth, nearer wins with GL_GREATER.
  glClipControl(GL_LOWER_LEFT, GL_ZERO_TO_ONE);
  glEnable(GL_DEPTH_TEST);
  glDisable(GL_CULL_FACE);  // scenes have thin two-sided walls
  glDisable(GL_BLEND);
  if (count) {
    const GLuint zero[4] = {0, 0, 0, 0};
    glNamedBufferSubData(stats_ssbo_, 0, 16, zero);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, ML_BINDING_STATS, stats_ssbo_);
  }
  glCheck("starting a frame");
}

// The G-buffer in deferred, and in forward when a GI pass needs it (forward
// shading writes no G-buffer); forward's depth pre-pass when the technique
// needs depth, or when counting without shading needs the bound's depth.
void FrameRenderer::depthPasses(bool deferred, const FrameOptions& options, const glm::mat4& view,
                                const glm::mat4& proj, LightAssigner& assigner) {
  const bool gi = options.shade && options.gi;
  if (deferred || gi) gbufferPass(deferred ? "gbuffer" : "gi-gbuffer", view, proj, assigner);
  if (!deferred && (assigner.needsDepth() || (options.count_lights && !options.shade))) {
    GlPassScope s(&gl_timer_, "depth-prepass");
    const GLfloat clear_depth = gpu::kSkyDepth;
    glBindFramebuffer(GL_FRAMEBUFFER, targets_->outputFbo());
    glDepthMask(GL_TRUE);
    glDepthFunc(GL_GREATER);
    glClearNamedFramebufferfv(targets_->outputFbo(), GL_DEPTH, 0, &clear_depth);
    glColorMask(GL_FALSE, GL_FALSE, GL_FALSE, GL_FALSE);
    const ShaderProgram& p = program("depth", assigner, false);
    p.use();
    setFrameUniforms(p, view, proj);
    scene_->draw(p, false);
    glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
  }
  glCheck("depth pass");
}

void FrameRenderer::gbufferPass(const char* name, const glm::mat4& view, const glm::mat4& proj,
                                LightAssigner& assigner) {
  GlPassScope s(&gl_timer_, name);
  const GLfloat clear_color[4] = {0, 0, 0, 1};
  const GLfloat clear_depth = gpu::kSkyDepth;
  glBindFramebuffer(GL_FRAMEBUFFER, targets_->gbufferFbo());
  glDepthMask(GL_TRUE);
  glDepthFunc(GL_GREATER);
  glClearNamedFramebufferfv(targets_->gbufferFbo(), GL_COLOR, 0, clear_color);
  glClearNamedFramebufferfv(targets_->gbufferFbo(), GL_COLOR, 1, clear_color);
  glClearNamedFramebufferfv(targets_->gbufferFbo(), GL_DEPTH, 0, &clear_depth);
  const ShaderProgram& p = program("gbuffer", assigner, false);
  p.use();
  setFrameUniforms(p, view, proj);
  scene_->draw(p, true);
  glCheck("G-buffer pass");
}

void FrameRenderer::assignLights(const Camera& camera, const glm::mat4& view, const glm::mat4& proj,
                                 LightAssigner& assigner, FrameResult& result) {
  const bool needs_depth = assigner.needsDepth();
  FrameInputs in{cl_,
                 camera,
                 camera.params(width_, height_),
                 view,
                 proj,
                 width_,
                 height_,
                 *lights_,
                 host_lights_,
                 light_count_,
                 lights_changed_,
                 needs_depth ? depth_.get() : nullptr,
                 cl_timer_,
                 result.passes,
                 &gl_timer_};
  // Shared-buffer hand-overs (share-acquire/-release/-copy) land in this frame's passes.
  struct ShareSink {
    ClRuntime& rt;
    ~ShareSink() { rt.setShareTimings(nullptr); }
  } sink{cl_};
  cl_.setShareTimings(&result.passes);
  assigner.assign(in);
  lights_changed_ = false;
}

void FrameRenderer::finishFrame(std::chrono::steady_clock::time_point t0, const LightAssigner& assigner,
                                FrameResult& result) {
  glFinish();
  cl_.queue().finish();
  result.host_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  // Device-side pass times, in pipeline order.
  PassTimings gl_cl;
  gl_timer_.collect(gl_cl);
  cl_timer_.collect(gl_cl);
  gl_cl.merge(result.passes);
  result.passes = gl_cl;
  result.memory_bytes = assigner.memoryBytes();
}

// 3. Shading: forward (re-drawing the scene, against the pre-pass depth when
// there is one) or one full-screen deferred pass over the G-buffer.
void FrameRenderer::shade(bool deferred, bool count, const glm::mat4& view, const glm::mat4& proj,
                          LightAssigner& assigner) {
  const GLfloat clear_color[4] = {0, 0, 0, 1};
  const GLuint clear_counts[4] = {0, 0, 0, 0};
  const GLfloat clear_depth = gpu::kSkyDepth;
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, ML_BINDING_LIGHTS, lights_->gl());
  glBindFramebuffer(GL_FRAMEBUFFER, targets_->outputFbo());
  glClearNamedFramebufferfv(targets_->outputFbo(), GL_COLOR, 0, clear_color);
  glClearNamedFramebufferuiv(targets_->outputFbo(), GL_COLOR, 1, clear_counts);
  if (deferred) {
    GlPassScope s(&gl_timer_, "deferred-shading");
    glDisable(GL_DEPTH_TEST);
    const ShaderProgram& p = program("deferred", assigner, count);
    p.use();
    setFrameUniforms(p, view, proj);
    assigner.bindForShading(p);
    glBindTextureUnit(ML_UNIT_GBUFFER_ALBEDO, targets_->albedoTexture());
    glBindTextureUnit(ML_UNIT_GBUFFER_NORMAL, targets_->normalTexture());
    glBindTextureUnit(ML_UNIT_GBUFFER_DEPTH, targets_->gbufferDepthTexture());
    glBindVertexArray(empty_vao_);
    glDrawArrays(GL_TRIANGLES, 0, 3);
    glBindVertexArray(0);
    glEnable(GL_DEPTH_TEST);
  } else {
    GlPassScope s(&gl_timer_, "forward-shading");
    if (assigner.needsDepth()) {
      shadeOnlyFirstEqualFragment();
    } else {
      glClearNamedFramebufferfv(targets_->outputFbo(), GL_DEPTH, 0, &clear_depth);
      glDepthFunc(GL_GREATER);
      glDepthMask(GL_TRUE);
    }
    const ShaderProgram& p = program("forward", assigner, count);
    p.use();
    setFrameUniforms(p, view, proj);
    assigner.bindForShading(p);
    scene_->draw(p, true);
    glDisable(GL_STENCIL_TEST);
    glDepthMask(GL_TRUE);
  }
  glCheck("shading pass");
}

void FrameRenderer::countLights(bool deferred, const glm::mat4& view, const glm::mat4& proj, FrameResult& result) {
  // The exact lower bound from this frame's depth: one CL pass, the same for
  // every technique (untimed: counted frames are not timed).
  cl::CommandQueue& q = cl_.queue();
  if (!bound_) bound_ = std::make_unique<ExactLowerBound>(cl_);
  if (bound_lights_stale_) bound_->setLights(q, host_lights_);
  bound_lights_stale_ = false;
  const std::size_t px = static_cast<std::size_t>(width_) * height_;
  if (!bound_counts_()) bound_counts_ = cl::Buffer(cl_.context(), CL_MEM_READ_WRITE, px * sizeof(cl_uint));
  readDepthInto(deferred);
  depth_->acquireForCl(q, ClAccess::Read);
  bound_->count(q, depth_->cl(), boundParams(view, proj, width_, height_), bound_counts_);
  std::vector<std::uint32_t> bound(px);
  q.enqueueReadBuffer(bound_counts_, CL_TRUE, 0, px * sizeof(cl_uint), bound.data());
  depth_->releaseToGl(q);

  const auto counts = targets_->readCounts();  // (evaluated, of those in range) per pixel
  const auto depth = targets_->readDepth(deferred);
  for (std::size_t i = 0; i < depth.size(); ++i) {
    if (gpu::is_sky_depth(depth[i])) continue;
    ++result.covered_pixels;
    result.lower_bound += bound[i];
    if (!result.shaded) continue;  // no shading pass: nothing was evaluated
    result.light_evaluations += counts[2 * i];
    if (bound[i] > counts[2 * i + 1]) result.missed_lights += bound[i] - counts[2 * i + 1];
  }
  if (!result.shaded) return;
  GLuint stats[2] = {0, 0};
  glGetNamedBufferSubData(stats_ssbo_, 0, sizeof stats, stats);
  result.fragment_evaluations = (static_cast<std::uint64_t>(stats[1]) << 32) | stats[0];
  glCheck("reading light counts");
}

}  // namespace ml
