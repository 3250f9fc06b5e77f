#include "host/view/Viewer.hpp"

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

#include <cstdio>

#include "host/view/FramePresenter.hpp"
#include "host/view/ImGuiLayer.hpp"
#include "host/view/ViewerPanel.hpp"

namespace ml {
namespace {

// The window's own input: Esc closes, F1 hides the panel, the scroll wheel zooms.
struct WindowInput {
  double scroll = 0;
  bool toggle_panel = false;
};
WindowInput g_input;

void onKey(GLFWwindow* window, int key, int, int action, int) {
  if (action != GLFW_PRESS) return;
  if (key == GLFW_KEY_ESCAPE) glfwSetWindowShouldClose(window, GLFW_TRUE);
  if (key == GLFW_KEY_F1) g_input.toggle_panel = true;
}

void onScroll(GLFWwindow*, double, double dy) { g_input.scroll += dy; }

}  // namespace

int runViewer(ViewerSetup setup, const DeviceChoice& device, std::optional<ViewerScript> script) {
  const unsigned width = setup.width, height = setup.height;
  RunContext ctx = RunContext::open(device, createWindowContext(int(width), int(height), "manylights view"));
  ctx.printDevices();
  GLFWwindow* window = glfwGetCurrentContext();
  ViewerSession session(ctx, std::move(setup));
  FramePresenter presenter;
  // Ours first: ImGui's GLFW backend chains to the callbacks installed before it.
  glfwSetKeyCallback(window, onKey);
  glfwSetScrollCallback(window, onScroll);
  ImGuiLayer imgui(window);
  PanelState panel;
  ScriptWindowActions window_actions;
  double last = glfwGetTime();
  while (!ctx.gl->shouldClose()) {
    const double now = glfwGetTime();
    if (script) {
      if (!script->step(session, window_actions)) break;
    } else {
      session.camera().handleInput(window, now - last, !imgui.wantsMouse(), !imgui.wantsKeyboard());
      if (g_input.scroll != 0.0 && !imgui.wantsMouse()) session.camera().onScroll(g_input.scroll);
    }
    g_input.scroll = 0;
    if (g_input.toggle_panel) window_actions.panel = !window_actions.panel;
    g_input.toggle_panel = false;
    last = now;
    const bool rendered = session.frame();
    int fw = 0, fh = 0;
    ctx.gl->framebufferSize(fw, fh);
    presenter.present(session, rendered, fw, fh);
    imgui.begin();
    if (window_actions.panel) drawPanel(session, panel);
    imgui.end();
    if (!window_actions.window_screenshot.empty()) {
      FramePresenter::saveWindow(window_actions.window_screenshot, fw, fh);
      std::printf("wrote %s\n", window_actions.window_screenshot.c_str());
      window_actions.window_screenshot.clear();
    }
    ctx.gl->swapBuffers();
    // Idle (nothing moved, no script): sleep until input instead of spinning a core.
    if (!script && !rendered) glfwWaitEventsTimeout(0.1);
  }
  return 0;
}

}  // namespace ml
