#pragma once
// An OpenGL 4.5 core context, current on the calling thread after creation.
// Two kinds behind one interface: headless EGL (render, bench, tests) and a
// GLFW window (interactive viewer). Functions are loaded through libepoxy.
// Creation failures are UserErrors that say what is missing.
#include <memory>
#include <string>

#include "host/cl/ClRuntime.hpp"

namespace ml {

class GlContext {
 public:
  virtual ~GlContext() = default;
  virtual void makeCurrent() = 0;
  // "GL 4.5 (Core Profile) Mesa 22.3.6 | llvmpipe (LLVM 15.0.6, 256 bits) | EGL surfaceless"
  virtual std::string describe() const = 0;
  // Handles for creating a CL context that shares with this GL context.
  virtual GlShareHandles shareHandles() const = 0;
  virtual bool hasWindow() const { return false; }
  virtual void swapBuffers() {}
  virtual bool shouldClose() { return false; }
  virtual void framebufferSize(int& w, int& h) const {
    w = 0;
    h = 0;
  }
};

// Headless EGL. $MANYLIGHTS_EGL selects the platform: "device" (EGL device,
// e.g. NVIDIA), "surfaceless" (Mesa), or unset: a hardware EGL device if one
// exists, else Mesa surfaceless, else the default display.
std::unique_ptr<GlContext> createHeadlessContext();
// A visible window (X11/Wayland through GLFW); vsync off.
std::unique_ptr<GlContext> createWindowContext(int width, int height, const std::string& title);

}  // namespace ml
