#pragma once
// Puts the session's current image into the window's framebuffer, scaled to
// the window: the shaded image straight from the renderer's output target, any
// other view mode (heat maps, debug views) through a texture uploaded when a
// new frame was rendered. Also reads the window back (panel included) for
// `screenshot_window`. Every GL call is checked.
#include <epoxy/gl.h>

#include <string>

namespace ml {

class ViewerSession;

class FramePresenter {
 public:
  FramePresenter() = default;
  FramePresenter(const FramePresenter&) = delete;
  FramePresenter& operator=(const FramePresenter&) = delete;
  ~FramePresenter();

  // `rendered`: the session drew a new frame since the last call.
  void present(ViewerSession& session, bool rendered, int window_width, int window_height);
  // The window's back buffer (call before swapping) to a PNG/EXR.
  static void saveWindow(const std::string& path, int window_width, int window_height);

 private:
  void upload(ViewerSession& session);
  GLuint texture_ = 0, fbo_ = 0;
  unsigned tex_w_ = 0, tex_h_ = 0;
  std::string uploaded_mode_;
};

}  // namespace ml
