#include "host/suite/CameraPathInterp.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace ml {

Camera cameraAt(const CameraPath& path, double t) {
  if (path.frames.empty()) throw std::invalid_argument("cameraAt: empty camera path");
  const double last = static_cast<double>(path.frames.size() - 1);
  t = std::isfinite(t) ? std::clamp(t, 0.0, last) : 0.0;
  const auto i = static_cast<std::size_t>(std::floor(t));
  if (i >= path.frames.size() - 1) return path.frames.back();
  const float f = static_cast<float>(t - static_cast<double>(i));
  const Camera& a = path.frames[i];
  const Camera& b = path.frames[i + 1];
  if (f == 0.0f) return a;
  auto mix = [f](float x, float y) { return x + (y - x) * f; };
  Camera c = a;
  c.eye = a.eye + (b.eye - a.eye) * f;
  c.center = a.center + (b.center - a.center) * f;
  c.up = a.up + (b.up - a.up) * f;
  c.fovy_degrees = mix(a.fovy_degrees, b.fovy_degrees);
  c.near_plane = mix(a.near_plane, b.near_plane);
  c.far_plane = mix(a.far_plane, b.far_plane);
  return c;
}

CameraPath resampleCameraPath(const CameraPath& path, std::size_t count) {
  if (count == 0) throw std::invalid_argument("resampleCameraPath: count must be at least 1");
  if (path.frames.empty()) throw std::invalid_argument("resampleCameraPath: empty camera path");
  CameraPath out;
  out.frames.reserve(count);
  const double span = static_cast<double>(path.frames.size() - 1);
  for (std::size_t i = 0; i < count; ++i) {
    const double t = count == 1 ? 0.0 : span * static_cast<double>(i) / static_cast<double>(count - 1);
    out.frames.push_back(cameraAt(path, t));
  }
  return out;
}

}  // namespace ml
