#include "host/assign/LightFootprint.hpp"

#include <algorithm>
#include <cmath>
#include <utility>

namespace ml {

double coveringLightPixels(const std::vector<gpu::PointLight>& lights, const gpu::CameraParams& cam) {
  const std::size_t stride = std::max<std::size_t>(1, lights.size() / kFootprintSamples);
  const float* v = cam.view;  // column-major
  const double tan_y = cam.tan_half_fovy, tan_x = tan_y * cam.aspect;
  const double pixels_per_unit = double(cam.height) / (2.0 * tan_y);  // at view distance 1
  std::vector<std::pair<double, double>> seen;                        // (radius in pixels, weight)
  for (std::size_t i = 0; i < lights.size(); i += stride) {
    const auto& p = lights[i].position_radius;
    const double x = v[0] * p.x + v[4] * p.y + v[8] * p.z + v[12];
    const double y = v[1] * p.x + v[5] * p.y + v[9] * p.z + v[13];
    const double z = -(v[2] * p.x + v[6] * p.y + v[10] * p.z + v[14]);
    const double r = p.w;
    if (!(z > r) || z - r > cam.far_plane) continue;  // reaches the camera, or beyond far
    if (std::fabs(x) > z * tan_x + r * std::sqrt(1.0 + tan_x * tan_x) ||
        std::fabs(y) > z * tan_y + r * std::sqrt(1.0 + tan_y * tan_y))
      continue;
    const double px = r * pixels_per_unit / z;
    seen.emplace_back(px, px * px);
  }
  if (seen.empty()) return 0.0;
  // The weighted median by selection, not a sort (the sort was most of the
  // time, and this runs every frame): the first radius in ascending order at
  // which the weights reach half their total.
  double target = 0.0;
  for (const auto& s : seen) target += s.second;
  target *= 0.5;
  auto first = seen.begin(), last = seen.end();
  while (last - first > 1) {
    const auto mid = first + (last - first) / 2;
    std::nth_element(first, mid, last);
    double left = 0.0;
    for (auto it = first; it != mid; ++it) left += it->second;
    if (left >= target) {
      last = mid;
    } else {
      target -= left;
      first = mid;
    }
  }
  return first->first;
}

unsigned tileForLights(double light_pixels, double per_radius, unsigned lo, unsigned hi) {
  if (!(light_pixels > 0.0)) return hi;
  unsigned t = hi;
  while (t > lo && double(t) > per_radius * light_pixels) t /= 2;
  return std::max(t, lo);
}

}  // namespace ml
