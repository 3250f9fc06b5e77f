#pragma once
// Light animation for `--animate FRACTION` (render and bench): every step()
// picks round(fraction * n) distinct lights at random and moves each by a
// uniform random offset of up to `speed` times its radius per axis, clamped to
// stay within `2 * speed` radii of where it started, so the set's bounds
// barely change and a dynamic structure can update instead of rebuild.
// Deterministic for a given seed: the same steps on every platform (own
// uniform mapping from std::mt19937_64, no std:: distributions).
#include <cstddef>
#include <cstdint>
#include <random>
#include <vector>

#include "host/scene/LightSet.hpp"
#include "host/shared/gpu_types.h"

namespace ml {

class LightAnimator {
 public:
  // UserError (naming --animate / --animate-speed) for a fraction outside
  // [0, 1] or a speed that is not positive and finite.
  LightAnimator(std::vector<gpu::PointLight> lights, double fraction, std::uint64_t seed = kThesisSeed,
                double speed = 0.25);

  std::size_t movesPerStep() const { return moves_; }
  const std::vector<gpu::PointLight>& step();
  const std::vector<gpu::PointLight>& lights() const { return now_; }
  // Indices moved by the last step (distinct).
  const std::vector<std::size_t>& lastMoved() const { return moved_; }

 private:
  double uniform(double a, double b);
  std::vector<gpu::PointLight> start_, now_;
  std::vector<std::size_t> order_, moved_;
  std::size_t moves_ = 0;
  double speed_ = 0.25;
  std::mt19937_64 rng_;
};

}  // namespace ml
