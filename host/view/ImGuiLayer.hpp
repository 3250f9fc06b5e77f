#pragma once
// Dear ImGui on the viewer's GLFW window (Debian's libimgui with its GLFW and
// OpenGL 3 backends): begin() starts a UI frame, end() draws it into the
// window's framebuffer. Owns the ImGui context; no ini file is written.
struct GLFWwindow;

namespace ml {

class ImGuiLayer {
 public:
  explicit ImGuiLayer(GLFWwindow* window);
  ~ImGuiLayer();
  ImGuiLayer(const ImGuiLayer&) = delete;
  ImGuiLayer& operator=(const ImGuiLayer&) = delete;

  void begin();
  void end();
  bool wantsMouse() const;
  bool wantsKeyboard() const;
};

}  // namespace ml
