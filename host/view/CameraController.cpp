#include "host/view/CameraController.hpp"

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <cmath>

namespace ml {
namespace {

glm::vec3 rotated(const glm::vec3& v, float degrees, const glm::vec3& axis) {
  return glm::vec3(glm::rotate(glm::mat4(1.0f), glm::radians(degrees), glm::normalize(axis)) * glm::vec4(v, 0.0f));
}

// Keeps the view direction off the up axis (a pitch of +-90 degrees would make `right` zero).
bool safePitch(const glm::vec3& dir, const glm::vec3& up) {
  return std::fabs(glm::dot(glm::normalize(dir), glm::normalize(up))) < 0.995f;
}

// The camera's axes, shared by fly, orbit and look: the view direction, the
// right axis (perpendicular to it and to up; zero when they are parallel) and up.
struct Basis {
  glm::vec3 forward, right, up;
};

Basis basisOf(const Camera& c) {
  const glm::vec3 forward = glm::normalize(c.center - c.eye), right = glm::cross(forward, c.up);
  return {forward, glm::length(right) > 0.0f ? glm::normalize(right) : glm::vec3(0.0f), glm::normalize(c.up)};
}

// `v` turned by `yaw` about up, then by `pitch` about the right axis unless
// that would bring it onto the up axis.
glm::vec3 turned(const glm::vec3& v, const Basis& b, float yaw_degrees, float pitch_degrees) {
  glm::vec3 out = rotated(v, yaw_degrees, b.up);
  if (pitch_degrees != 0.0f && glm::length(b.right) > 0.0f) {
    const glm::vec3 pitched = rotated(out, pitch_degrees, b.right);
    if (safePitch(pitched, b.up)) out = pitched;
  }
  return out;
}

}  // namespace

void CameraController::set(const Camera& c) {
  camera_ = c;
  ++version_;
}

void CameraController::orbit(float yaw_degrees, float pitch_degrees) {
  camera_.eye = camera_.center + turned(camera_.eye - camera_.center, basisOf(camera_), yaw_degrees, pitch_degrees);
  ++version_;
}

void CameraController::look(float yaw_degrees, float pitch_degrees) {
  camera_.center = camera_.eye + turned(camera_.center - camera_.eye, basisOf(camera_), yaw_degrees, pitch_degrees);
  ++version_;
}

void CameraController::fly(float forward, float right, float up) {
  const Basis b = basisOf(camera_);
  const glm::vec3 d = forward * b.forward + right * b.right + up * b.up;
  camera_.eye += d;
  camera_.center += d;
  ++version_;
}

void CameraController::onScroll(double dy) {
  // Zoom: the eye moves 10% of its distance to the centre per notch (both modes).
  const glm::vec3 offset = camera_.eye - camera_.center;
  camera_.eye = camera_.center + offset * static_cast<float>(std::pow(0.9, dy));
  ++version_;
}

void CameraController::handleInput(GLFWwindow* window, double dt, bool mouse_free, bool keys_free) {
  double x = 0, y = 0;
  glfwGetCursorPos(window, &x, &y);
  const int button = mode == CameraMode::Fly ? GLFW_MOUSE_BUTTON_RIGHT : GLFW_MOUSE_BUTTON_LEFT;
  const bool down = mouse_free && glfwGetMouseButton(window, button) == GLFW_PRESS;
  if (down && dragging_) {
    const float dx = static_cast<float>(x - last_x_) * 0.25f, dy = static_cast<float>(y - last_y_) * 0.25f;
    if (dx != 0.0f || dy != 0.0f) {
      if (mode == CameraMode::Fly) look(-dx, -dy);
      else orbit(-dx, -dy);
    }
  }
  dragging_ = down;
  last_x_ = x;
  last_y_ = y;
  if (!keys_free || mode != CameraMode::Fly) return;
  auto key = [&](int k) { return glfwGetKey(window, k) == GLFW_PRESS ? 1.0f : 0.0f; };
  const float step = speed * glm::length(camera_.center - camera_.eye) * static_cast<float>(dt);
  const float f = key(GLFW_KEY_W) - key(GLFW_KEY_S), r = key(GLFW_KEY_D) - key(GLFW_KEY_A),
              u = key(GLFW_KEY_E) - key(GLFW_KEY_Q);
  if (f != 0.0f || r != 0.0f || u != 0.0f) fly(f * step, r * step, u * step);
}

}  // namespace ml
