#include "host/scene/LightAnimator.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "host/util/Error.hpp"

namespace ml {

LightAnimator::LightAnimator(std::vector<gpu::PointLight> lights, double fraction, std::uint64_t seed, double speed)
    : start_(lights), now_(std::move(lights)), speed_(speed), rng_(seed) {
  if (!(fraction >= 0.0 && fraction <= 1.0))
    throw UserError("--animate: expected a fraction of the lights in [0, 1], got " + std::to_string(fraction));
  if (!(speed > 0.0 && std::isfinite(speed)))
    throw UserError("--animate-speed: expected a positive step (times the light radius), got " +
                    std::to_string(speed));
  moves_ = std::min(now_.size(), static_cast<std::size_t>(std::llround(fraction * double(now_.size()))));
  order_.resize(now_.size());
  for (std::size_t i = 0; i < order_.size(); ++i) order_[i] = i;
}

double LightAnimator::uniform(double a, double b) { return a + (b - a) * double(rng_() >> 11) * 0x1.0p-53; }

const std::vector<gpu::PointLight>& LightAnimator::step() {
  // Partial Fisher-Yates: the first moves_ entries of order_ become a uniform
  // random subset of distinct indices.
  const std::size_t n = order_.size();
  for (std::size_t k = 0; k < moves_; ++k) std::swap(order_[k], order_[k + rng_() % (n - k)]);
  moved_.assign(order_.begin(), order_.begin() + static_cast<std::ptrdiff_t>(moves_));
  for (std::size_t i : moved_) {
    auto& p = now_[i].position_radius;
    const auto& s = start_[i].position_radius;
    const float r = p.w;
    auto move = [&](float& v, float origin) {
      const float reach = float(2.0 * speed_) * r;
      v = std::clamp(v + float(uniform(-speed_, speed_)) * r, origin - reach, origin + reach);
    };
    move(p.x, s.x);
    move(p.y, s.y);
    move(p.z, s.z);
  }
  return now_;
}

}  // namespace ml
