#include "gl/RenderTargets.hpp"

#include <unistd.h>

#include <algorithm>
#include <stdexcept>
#include <string>
#include <utility>

#include "gl/GlCheck.hpp"
#include "gl/Texture2d.hpp"
#include "host/util/Error.hpp"

namespace ml {
namespace {
struct TargetFormat {
  GLenum internal, format, type;
  const char* name;
};
// Every texture the constructor makes (the two 32F depths share a row).
constexpr TargetFormat kFormats[] = {
    {GL_RGBA32F, GL_RGBA, GL_FLOAT, "RGBA32F colour"},
    {GL_RG32UI, GL_RG_INTEGER, GL_UNSIGNED_INT, "RG32UI light-count"},
    {GL_DEPTH32F_STENCIL8, GL_DEPTH_STENCIL, GL_FLOAT_32_UNSIGNED_INT_24_8_REV, "depth-stencil"},
    {GL_RGBA8, GL_RGBA, GL_UNSIGNED_BYTE, "RGBA8 albedo"},
    {GL_RG16, GL_RG, GL_UNSIGNED_SHORT, "RG16 normal"},
    {GL_DEPTH_COMPONENT32F, GL_DEPTH_COMPONENT, GL_FLOAT, "32F depth"},
};

GLint glInt(GLenum e) {
  GLint v = 0;
  glGetIntegerv(e, &v);
  return v;
}

std::string dims(unsigned w, unsigned h) { return std::to_string(w) + "x" + std::to_string(h); }
std::string mib(std::size_t bytes) { return std::to_string(bytes >> 20) + " MiB"; }

// A proxy texture asks the driver whether it would create the texture,
// without allocating it (Mesa: pipe_screen::can_create_resource).
bool proxyAccepts(const TargetFormat& f, unsigned w, unsigned h) {
  glTexImage2D(GL_PROXY_TEXTURE_2D, 0, static_cast<GLint>(f.internal), static_cast<GLsizei>(w),
               static_cast<GLsizei>(h), 0, f.format, f.type, nullptr);
  GLint got = 0;
  glGetTexLevelParameteriv(GL_PROXY_TEXTURE_2D, 0, GL_TEXTURE_WIDTH, &got);
  return got != 0;
}

struct SizeLimits {
  unsigned max_w, max_h;
  std::size_t budget;
};

// Why w x h cannot be made; empty if it can.
std::string whyNot(unsigned w, unsigned h, const SizeLimits& l) {
  if (w > l.max_w || h > l.max_h) return "over the GL limit of " + dims(l.max_w, l.max_h) + " pixels";
  const std::size_t bytes = std::size_t(w) * h * RenderTargets::kBytesPerPixel;
  if (bytes > l.budget) return "the render targets would need " + mib(bytes) + ", over the budget of " + mib(l.budget);
  for (const TargetFormat& f : kFormats)
    if (!proxyAccepts(f, w, h)) return "the GL driver refuses a " + dims(w, h) + " " + f.name + " texture";
  return {};
}

// Largest s * (w, h) / max(w, h), s = 1..max(w, h), that whyNot accepts; {0, 0} if none.
std::pair<unsigned, unsigned> largestAtAspect(unsigned w, unsigned h, const SizeLimits& l) {
  const unsigned side = std::max(w, h);
  auto at = [&](unsigned s) {
    return std::pair<unsigned, unsigned>(std::max(1u, unsigned(std::uint64_t(w) * s / side)),
                                         std::max(1u, unsigned(std::uint64_t(h) * s / side)));
  };
  unsigned lo = 0, hi = side;  // whyNot accepts at(lo) (lo > 0), refuses at(hi)
  while (hi - lo > 1) {
    const unsigned mid = lo + (hi - lo) / 2;
    const auto [mw, mh] = at(mid);
    (whyNot(mw, mh, l).empty() ? lo : hi) = mid;
  }
  return lo ? at(lo) : std::pair<unsigned, unsigned>(0, 0);
}

void checkComplete(GLuint fbo, const char* what) {
  GLenum status = glCheckNamedFramebufferStatus(fbo, GL_FRAMEBUFFER);
  if (status != GL_FRAMEBUFFER_COMPLETE)
    throw std::runtime_error(std::string("framebuffer '") + what + "' incomplete: " + std::to_string(status));
}
}  // namespace

std::size_t RenderTargets::memoryBudget() {
  const long pages = sysconf(_SC_PHYS_PAGES), page = sysconf(_SC_PAGESIZE);
  std::size_t budget = pages > 0 && page > 0 ? std::size_t(pages) * std::size_t(page) / 2 : std::size_t(4) << 30;
  if (epoxy_has_gl_extension("GL_NVX_gpu_memory_info")) {
    const GLint kib = glInt(GL_GPU_MEMORY_INFO_DEDICATED_VIDMEM_NVX);
    if (kib > 0) budget = std::min(budget, std::size_t(kib) << 10);
  }
  return budget;
}

void RenderTargets::checkSize(unsigned width, unsigned height) {
  GLint vp[2] = {0, 0};
  glGetIntegerv(GL_MAX_VIEWPORT_DIMS, vp);
  const GLint tex = std::min(glInt(GL_MAX_TEXTURE_SIZE), glInt(GL_MAX_RENDERBUFFER_SIZE));
  const SizeLimits l{unsigned(std::max(0, std::min({tex, vp[0], glInt(GL_MAX_FRAMEBUFFER_WIDTH)}))),
                     unsigned(std::max(0, std::min({tex, vp[1], glInt(GL_MAX_FRAMEBUFFER_HEIGHT)}))), memoryBudget()};
  const GLint unpack = glInt(GL_PIXEL_UNPACK_BUFFER_BINDING);
  glBindBuffer(GL_PIXEL_UNPACK_BUFFER, 0);  // proxies read no pixels, but a bound buffer would make nullptr an offset
  const std::string why = whyNot(width, height, l);
  const auto [lw, lh] = why.empty() ? std::pair<unsigned, unsigned>() : largestAtAspect(width, height, l);
  glBindBuffer(GL_PIXEL_UNPACK_BUFFER, static_cast<GLuint>(unpack));
  glCheck("checking the render-target size");
  if (why.empty()) return;
  throw UserError("--size " + dims(width, height) + ": " + why + "; the largest size of this aspect ratio is " +
                  (lw ? dims(lw, lh) : std::string("none")) + " (GL limit " + dims(l.max_w, l.max_h) +
                  ", render-target budget " + mib(l.budget) + ")");
}

RenderTargets::RenderTargets(unsigned width, unsigned height) : width_(width), height_(height) {
  checkSize(width, height);
  color_ = makeTexture2d(GL_RGBA32F, width, height);
  counts_ = makeTexture2d(GL_RG32UI, width, height);
  depth_ = makeTexture2d(GL_DEPTH32F_STENCIL8, width, height);
  glCreateFramebuffers(1, &output_fbo_);
  glNamedFramebufferTexture(output_fbo_, GL_COLOR_ATTACHMENT0, color_, 0);
  glNamedFramebufferTexture(output_fbo_, GL_COLOR_ATTACHMENT1, counts_, 0);
  glNamedFramebufferTexture(output_fbo_, GL_DEPTH_STENCIL_ATTACHMENT, depth_, 0);
  const GLenum bufs[2] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1};
  glNamedFramebufferDrawBuffers(output_fbo_, 2, bufs);
  checkComplete(output_fbo_, "output");

  albedo_ = makeTexture2d(GL_RGBA8, width, height);
  normal_ = makeTexture2d(GL_RG16, width, height);  // octahedral normals (gl/shaders/common/octahedral.glsl)
  gbuffer_depth_ = makeTexture2d(GL_DEPTH_COMPONENT32F, width, height);
  glCreateFramebuffers(1, &gbuffer_fbo_);
  glNamedFramebufferTexture(gbuffer_fbo_, GL_COLOR_ATTACHMENT0, albedo_, 0);
  glNamedFramebufferTexture(gbuffer_fbo_, GL_COLOR_ATTACHMENT1, normal_, 0);
  glNamedFramebufferTexture(gbuffer_fbo_, GL_DEPTH_ATTACHMENT, gbuffer_depth_, 0);
  glNamedFramebufferDrawBuffers(gbuffer_fbo_, 2, bufs);
  checkComplete(gbuffer_fbo_, "gbuffer");
  glCheck("creating render targets");
}

RenderTargets::~RenderTargets() {
  GLuint fbos[2] = {output_fbo_, gbuffer_fbo_};
  glDeleteFramebuffers(2, fbos);
  GLuint texs[6] = {color_, counts_, depth_, albedo_, normal_, gbuffer_depth_};
  glDeleteTextures(6, texs);
}

std::vector<float> RenderTargets::readColor() const {
  std::vector<float> px(static_cast<size_t>(width_) * height_ * 4);
  glGetTextureImage(color_, 0, GL_RGBA, GL_FLOAT, static_cast<GLsizei>(px.size() * sizeof(float)), px.data());
  glCheck("reading the colour target");
  return px;
}

std::vector<std::uint32_t> RenderTargets::readCounts() const {
  std::vector<std::uint32_t> px(static_cast<size_t>(width_) * height_ * 2);
  glGetTextureImage(counts_, 0, GL_RG_INTEGER, GL_UNSIGNED_INT, static_cast<GLsizei>(px.size() * sizeof(std::uint32_t)),
                    px.data());
  glCheck("reading the light-count target");
  return px;
}

std::vector<float> RenderTargets::readDepth(bool deferred) const {
  std::vector<float> px(static_cast<size_t>(width_) * height_);
  glGetTextureImage(deferred ? gbuffer_depth_ : depth_, 0, GL_DEPTH_COMPONENT, GL_FLOAT,
                    static_cast<GLsizei>(px.size() * sizeof(float)), px.data());
  glCheck("reading depth");
  return px;
}

}  // namespace ml
