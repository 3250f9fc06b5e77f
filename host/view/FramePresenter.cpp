#include "host/view/FramePresenter.hpp"

#include <vector>

#include "gl/GlCheck.hpp"
#include "host/run/OutputFiles.hpp"
#include "host/view/ViewerSession.hpp"

namespace ml {

FramePresenter::~FramePresenter() {
  if (fbo_) glDeleteFramebuffers(1, &fbo_);
  if (texture_) glDeleteTextures(1, &texture_);
}

void FramePresenter::upload(ViewerSession& session) {
  const std::vector<float> rgba = session.image();
  if (!texture_ || tex_w_ != session.width() || tex_h_ != session.height()) {
    if (fbo_) glDeleteFramebuffers(1, &fbo_);
    if (texture_) glDeleteTextures(1, &texture_);
    tex_w_ = session.width();
    tex_h_ = session.height();
    glCreateTextures(GL_TEXTURE_2D, 1, &texture_);
    glTextureStorage2D(texture_, 1, GL_RGBA32F, GLsizei(tex_w_), GLsizei(tex_h_));
    glCreateFramebuffers(1, &fbo_);
    glNamedFramebufferTexture(fbo_, GL_COLOR_ATTACHMENT0, texture_, 0);
    glNamedFramebufferReadBuffer(fbo_, GL_COLOR_ATTACHMENT0);
    glCheck("creating the viewer's image texture");
  }
  glTextureSubImage2D(texture_, 0, 0, 0, GLsizei(tex_w_), GLsizei(tex_h_), GL_RGBA, GL_FLOAT, rgba.data());
  glCheck("uploading the viewer's image");
  uploaded_mode_ = session.viewMode();
}

void FramePresenter::present(ViewerSession& session, bool rendered, int window_width, int window_height) {
  GLuint source = 0;
  if (session.viewMode() == "shaded") {
    source = session.renderer().targets().outputFbo();
    glNamedFramebufferReadBuffer(source, GL_COLOR_ATTACHMENT0);
  } else {
    if (rendered || uploaded_mode_ != session.viewMode()) upload(session);
    source = fbo_;
  }
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  glViewport(0, 0, window_width, window_height);
  glClearColor(0.0f, 0.0f, 0.0f, 1.0f);
  glClear(GL_COLOR_BUFFER_BIT);
  glBlitNamedFramebuffer(source, 0, 0, 0, GLint(session.width()), GLint(session.height()), 0, 0, window_width,
                         window_height, GL_COLOR_BUFFER_BIT, GL_LINEAR);
  glCheck("presenting the frame in the window");
}

void FramePresenter::saveWindow(const std::string& path, int window_width, int window_height) {
  requireImageFile("screenshot_window", path);
  std::vector<float> px(std::size_t(window_width) * std::size_t(window_height) * 4);
  glBindFramebuffer(GL_READ_FRAMEBUFFER, 0);
  glReadBuffer(GL_BACK);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glReadPixels(0, 0, window_width, window_height, GL_RGBA, GL_FLOAT, px.data());
  glCheck("reading the window back");
  writeImageAtomically("screenshot_window", path, unsigned(window_width), unsigned(window_height), 4, px);
}

}  // namespace ml
