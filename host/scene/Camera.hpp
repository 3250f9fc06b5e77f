#pragma once
// Pinhole camera (right-handed, looking down -z in view space, OpenGL clip
// conventions with reversed-Z depth: host/shared/depth_convention.h) and
// camera paths.
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

// The depth range a reversed-Z float depth buffer resolves: with near at least
// kMinNearPlane and far / near at most kMaxFarOverNear, the window depth of
// every visible point is a normal float (drivers may flush denormals to 0,
// which reads as sky), with a wide margin for the rasteriser's interpolation.
inline constexpr float kMinNearPlane = 1e-30f;
inline constexpr float kMaxFarOverNear = 1e30f;
// Throws UserError "<where>: ..." naming the limit unless 0 < near < far lie
// within those limits (and are finite).
void checkDepthRange(const Camera& c, const std::string& where);

struct CameraPath {
  std::vector<Camera> frames;  // never empty after loading
};

// Throws UserError naming the file on missing file, bad JSON or bad fields.
CameraPath loadCameraJson(const std::string& path);
void saveCameraJson(const std::string& path, const CameraPath& path_data);

}  // namespace ml
