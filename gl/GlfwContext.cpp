// A window with a GL 4.5 core context through GLFW (used by the viewer).
// Project headers (and opencl.hpp) come first: X11's headers define macros such
// as None and Status that break opencl.hpp.
#include "gl/GlCheck.hpp"
#include "gl/GlContext.hpp"
#include "host/util/Error.hpp"

#include <epoxy/gl.h>
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#define GLFW_EXPOSE_NATIVE_X11
#define GLFW_EXPOSE_NATIVE_GLX
#include <GLFW/glfw3native.h>

#include <string>

namespace ml {
namespace {

std::string g_glfw_error;
void onGlfwError(int, const char* description) { g_glfw_error = description ? description : "unknown"; }

class GlfwContext final : public GlContext {
 public:
  GlfwContext(int width, int height, const std::string& title) {
    glfwSetErrorCallback(onGlfwError);
    if (!glfwInit()) throw UserError("GLFW could not initialise a window system: " + g_glfw_error +
                                     " (no display? use `render` for headless output, or run under xvfb-run)");
    glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 4);
    glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 5);
    glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
    glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
#ifndef NDEBUG
    glfwWindowHint(GLFW_OPENGL_DEBUG_CONTEXT, GLFW_TRUE);
#endif
    window_ = glfwCreateWindow(width, height, title.c_str(), nullptr, nullptr);
    if (!window_) {
      glfwTerminate();
      throw UserError("GLFW could not create a GL 4.5 core window: " + g_glfw_error);
    }
    makeCurrent();
    glfwSwapInterval(0);
    installGlDebugOutput();
  }
  ~GlfwContext() override {
    if (window_) glfwDestroyWindow(window_);
    glfwTerminate();
  }
  void makeCurrent() override { glfwMakeContextCurrent(window_); }
  std::string describe() const override {
    return std::string("OpenGL: ") + reinterpret_cast<const char*>(glGetString(GL_VERSION)) + " | " +
           reinterpret_cast<const char*>(glGetString(GL_RENDERER)) + " | GLFW window";
  }
  GlShareHandles shareHandles() const override {
    GlShareHandles h;
    // Debian's GLFW 3.3 is the X11 build; GLX handles are what CL-GL sharing needs there.
    h.glx_display = glfwGetX11Display();
    h.glx_context = h.glx_display ? glfwGetGLXContext(window_) : nullptr;
    const GLubyte* r = glGetString(GL_RENDERER);
    h.renderer = r ? reinterpret_cast<const char*>(r) : "";
    return h;
  }
  bool hasWindow() const override { return true; }
  void swapBuffers() override {
    glfwSwapBuffers(window_);
    glfwPollEvents();
  }
  bool shouldClose() override { return glfwWindowShouldClose(window_); }
  void framebufferSize(int& w, int& h) const override { glfwGetFramebufferSize(window_, &w, &h); }
  GLFWwindow* window() const { return window_; }

 private:
  GLFWwindow* window_ = nullptr;
};

}  // namespace

std::unique_ptr<GlContext> createWindowContext(int width, int height, const std::string& title) {
  return std::make_unique<GlfwContext>(width, height, title);
}

}  // namespace ml
