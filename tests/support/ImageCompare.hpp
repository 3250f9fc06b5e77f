#pragma once
// Image comparison for rendering tests: RGBA float images of equal size,
// compared as displayed (each channel clamped to [0, 1]).
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <vector>

namespace ml::test {

struct ImageDiff {
  double mean_abs = 0;        // mean |a-b| over RGB of all pixels
  double max_abs = 0;         // largest |a-b| of any channel
  double frac_over_tol = 0;   // fraction of pixels with any channel differing by more than tol
};

inline ImageDiff compareImages(const std::vector<float>& a, const std::vector<float>& b, double tol) {
  ImageDiff d;
  const std::size_t px = a.size() / 4;
  std::size_t over = 0;
  for (std::size_t i = 0; i < px; ++i) {
    bool bad = false;
    for (int c = 0; c < 3; ++c) {
      const double e = std::fabs(std::clamp(double(a[4 * i + c]), 0.0, 1.0) - std::clamp(double(b[4 * i + c]), 0.0, 1.0));
      d.mean_abs += e;
      if (e > d.max_abs) d.max_abs = e;
      if (e > tol) bad = true;
    }
    over += bad;
  }
  d.mean_abs /= double(px * 3);
  d.frac_over_tol = double(over) / double(px);
  return d;
}

// Standard deviation of luminance: a uniform image has ~0.
inline double luminanceStdDev(const std::vector<float>& img) {
  const std::size_t px = img.size() / 4;
  double s = 0, s2 = 0;
  for (std::size_t i = 0; i < px; ++i) {
    const double l = 0.2126 * img[4 * i] + 0.7152 * img[4 * i + 1] + 0.0722 * img[4 * i + 2];
    s += l;
    s2 += l * l;
  }
  const double m = s / double(px);
  return std::sqrt(std::max(0.0, s2 / double(px) - m * m));
}

}  // namespace ml::test
