#pragma once
// What a technique's debug view gets besides its own state: the frame's
// window depth and the camera's unprojection, so a view can colour each pixel
// by a property of its surface point (hashed shading's octree cell) and not
// only by what the technique stored per pixel (clustered's cluster map).
// Built by the run layer from the frame just rendered (frameDebugView in
// host/run/RunLayer.hpp), the same way for `render --NAME-view` and the
// viewer, so both show the same image.
#include <glm/glm.hpp>

#include <vector>

#include "host/shared/gpu_types.h"

namespace ml {

struct DebugViewInputs {
  unsigned width = 0, height = 0;
  // Window depth (host/shared/depth_convention.h), width * height, row 0 at the bottom.
  std::vector<float> depth;
  // The inverse view matrix and the projection, as the lower bound's kernel
  // reads them (boundParams): windowToWorld is the one place depth becomes a
  // position, so a view and the lower bound agree on every pixel's point.
  gpu::BoundParams unproject{};

  // Pixel (x, y)'s surface point (windowToWorld); false for sky.
  bool worldAt(unsigned x, unsigned y, glm::vec3& world) const;
};

}  // namespace ml
