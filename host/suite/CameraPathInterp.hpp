#pragma once
// Sampling a camera path between its key frames: for sub-frame sampling and
// for resampling a path to a different number of frames (e.g. a short path
// stretched over a long benchmark, or a long one thinned out).
//
// Contract: `t` is in key-frame units (t = 2.5 is halfway between frames 2 and
// 3) and is clamped to [0, frames - 1]. eye, center and up are interpolated
// linearly, component-wise; up is not renormalised (lookAt does that), and the
// lens (fovy, near, far) is interpolated linearly too. A linear blend of two
// valid poses can only degenerate (eye == center, or up parallel to the view
// direction) when the path itself turns by about 180 degrees between two key
// frames; callers that need a guarantee check the result.
#include <cstddef>

#include "host/scene/Camera.hpp"

namespace ml {

Camera cameraAt(const CameraPath& path, double t);

// `count` frames spread evenly from the first key frame to the last (both
// included; count == 1 gives the first frame). Throws std::invalid_argument
// for count == 0 or an empty path.
CameraPath resampleCameraPath(const CameraPath& path, std::size_t count);

}  // namespace ml
