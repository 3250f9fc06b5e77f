#pragma once
// The viewer's camera: fly (WASD/QE move, right mouse drag looks) or orbit
// (left mouse drag turns the eye around the centre, scroll zooms). Moves are
// in scene units scaled by the distance eye->centre, so any scene size feels
// alike. version() grows with every change, so the session re-renders only
// when the camera moved. Near/far/fovy are kept from the camera set.
#include <cstdint>

#include "host/scene/Camera.hpp"

struct GLFWwindow;

namespace ml {

enum class CameraMode { Fly, Orbit };

class CameraController {
 public:
  const Camera& camera() const { return camera_; }
  void set(const Camera& c);
  // Turns the eye about the centre: yaw about `up`, pitch about the camera's right axis (degrees).
  void orbit(float yaw_degrees, float pitch_degrees);
  // Moves eye and centre together along the view direction, the right axis
  // (perpendicular to it and to up) and the camera's up (scene units).
  void fly(float forward, float right, float up);
  // Turns the view direction about the eye (degrees), centre follows.
  void look(float yaw_degrees, float pitch_degrees);
  // Keyboard and mouse of `window` over `dt` seconds; `mouse_free` false when the panel has the mouse.
  void handleInput(GLFWwindow* window, double dt, bool mouse_free, bool keys_free);
  void onScroll(double dy);

  CameraMode mode = CameraMode::Fly;
  float speed = 1.0f;  // fly speed: distance eye->centre per second
  std::uint64_t version() const { return version_; }

 private:
  Camera camera_;
  std::uint64_t version_ = 0;
  double last_x_ = 0, last_y_ = 0;
  bool dragging_ = false;
};

}  // namespace ml
