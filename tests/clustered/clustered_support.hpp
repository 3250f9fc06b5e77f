#pragma once
// Random views for the clustered tests (support/RandomView.hpp, with depths
// across the whole range and tiny lights at the near plane).
#include "support/RandomView.hpp"

namespace ml::test {

using ClusterCase = RandomView;

// Rectangles anywhere up to 80% of the far plane, and tiny lights at the near plane.
inline ClusterCase randomClusterCase(std::mt19937_64& rng, unsigned w, unsigned h, std::size_t n_lights,
                                     float far_plane = 100.0f) {
  return randomView(rng, w, h, n_lights, {far_plane, 0.11f, 0.8f * far_plane, 0.3f, 0.1f, true});
}

}  // namespace ml::test
