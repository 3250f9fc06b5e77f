#include "gl/RenderTargets.hpp"

#include <stdexcept>
#include <string>

#include "gl/GlCheck.hpp"

namespace ml {
namespace {
GLuint makeTexture(GLenum format, unsigned w, unsigned h) {
  GLuint t = 0;
  glCreateTextures(GL_TEXTURE_2D, 1, &t);
  glTextureStorage2D(t, 1, format, static_cast<GLsizei>(w), static_cast<GLsizei>(h));
  glTextureParameteri(t, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
  glTextureParameteri(t, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
  return t;
}
void checkComplete(GLuint fbo, const char* what) {
  GLenum status = glCheckNamedFramebufferStatus(fbo, GL_FRAMEBUFFER);
  if (status != GL_FRAMEBUFFER_COMPLETE)
    throw std::runtime_error(std::string("framebuffer '") + what + "' incomplete: " + std::to_string(status));
}
}  // namespace

RenderTargets::RenderTargets(unsigned width, unsigned height) : width_(width), height_(height) {
  color_ = makeTexture(GL_RGBA32F, width, height);
  counts_ = makeTexture(GL_RG32UI, width, height);
  depth_ = makeTexture(GL_DEPTH_COMPONENT32F, width, height);
  glCreateFramebuffers(1, &output_fbo_);
  glNamedFramebufferTexture(output_fbo_, GL_COLOR_ATTACHMENT0, color_, 0);
  glNamedFramebufferTexture(output_fbo_, GL_COLOR_ATTACHMENT1, counts_, 0);
  glNamedFramebufferTexture(output_fbo_, GL_DEPTH_ATTACHMENT, depth_, 0);
  const GLenum bufs[2] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1};
  glNamedFramebufferDrawBuffers(output_fbo_, 2, bufs);
  checkComplete(output_fbo_, "output");

  albedo_ = makeTexture(GL_RGBA8, width, height);
  normal_ = makeTexture(GL_RG16, width, height);  // octahedral normals (gl/shaders/octahedral.glsl)
  gbuffer_depth_ = makeTexture(GL_DEPTH_COMPONENT32F, width, height);
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
