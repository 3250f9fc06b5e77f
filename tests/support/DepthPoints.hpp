#pragma once
// Surface points of depth-buffer pixels for the tests' independent CPU
// references: the distance from the depth convention's own inversion
// (gpu::linear_depth, host/shared/depth_convention.h; ~1e-7 relative at any
// near/far), the rest in double along the pixel centre's ray, so the reference
// adds no rounding of its own that compares with the techniques' padding.
#include <glm/glm.hpp>

#include "host/scene/Camera.hpp"
#include "host/shared/gpu_types.h"

namespace ml::test {

// World point of pixel (x, y) (row 0 at the bottom) with window depth d (not sky).
inline glm::dvec3 pixelWorldPoint(const Camera& cam, const gpu::CameraParams& p, unsigned x, unsigned y, float d) {
  const double z = gpu::linear_depth(d, p);
  const double nx = (x + 0.5) / p.width * 2 - 1, ny = (y + 0.5) / p.height * 2 - 1;
  const glm::dvec4 view{(nx + p.proj[8]) * z / p.proj[0], (ny + p.proj[9]) * z / p.proj[5], -z, 1.0};
  return glm::dvec3(glm::inverse(glm::dmat4(cam.view())) * view);
}

}  // namespace ml::test
