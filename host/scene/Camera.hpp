#pragma once
// Pinhole camera (right-handed, looking down -z in view space, OpenGL clip
// conventions) and camera paths.
//
// JSON: a single camera {"eye":[..], "center":[..], "up":[..], "fovy": deg,
// "near": n, "far": f}, or a path {"frames": [{eye, center, up}, ...], "fovy"...};
// the nTiled suite's camera.json (frames of {eye, center, up}) loads the same way.
#include <glm/glm.hpp>

#include <string>
#include <vector>

#include "host/shared/gpu_types.h"

namespace ml {

struct Camera {
  glm::vec3 eye{0.0f, 0.0f, 5.0f};
  glm::vec3 center{0.0f};
  glm::vec3 up{0.0f, 1.0f, 0.0f};
  float fovy_degrees = 45.0f;
  float near_plane = 0.1f;
  float far_plane = 1000.0f;

  glm::mat4 view() const;
  glm::mat4 projection(float aspect) const;
  // Fills the struct the kernels read (column-major matrices).
  gpu::CameraParams params(unsigned width, unsigned height) const;
};

struct CameraPath {
  std::vector<Camera> frames;  // never empty after loading
};

// Throws UserError naming the file on missing file, bad JSON or bad fields.
CameraPath loadCameraJson(const std::string& path);
void saveCameraJson(const std::string& path, const CameraPath& path_data);

}  // namespace ml
