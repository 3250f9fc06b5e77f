#include "host/util/GiToneMap.hpp"

#include <cstddef>

namespace ml {

std::vector<float> giToneMapped(const std::vector<float>& rgba) {
  double sum = 0;
  std::size_t covered = 0;
  for (std::size_t i = 0; i + 3 < rgba.size(); i += 4)
    if (rgba[i + 3] > 0) {
      sum += 0.2126 * rgba[i] + 0.7152 * rgba[i + 1] + 0.0722 * rgba[i + 2];
      ++covered;
    }
  const float key = covered && sum > 0 ? float(sum / double(covered)) : 1.0f;
  std::vector<float> px(rgba);
  for (std::size_t i = 0; i < px.size(); ++i) px[i] = i % 4 == 3 ? 1.0f : px[i] / (px[i] + key);
  return px;
}

}  // namespace ml
