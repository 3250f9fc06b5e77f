// LightAnimator (--animate): each step moves exactly round(fraction * n)
// distinct lights, leaves the others bit-identical, keeps every light within
// twice the step of its start, is deterministic per seed, and rejects bad
// fractions and speeds with the flag's name.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <set>

#include "host/scene/LightAnimator.hpp"
#include "host/util/Error.hpp"

namespace ml {
namespace {

std::vector<gpu::PointLight> randomLights(std::size_t n, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<float> u(-20.f, 20.f), r(0.5f, 4.f);
  std::vector<gpu::PointLight> out(n);
  for (auto& l : out) {
    l.position_radius = {u(rng), u(rng), u(rng), r(rng)};
    l.color = {1, 1, 1, 1};
  }
  return out;
}

TEST(LightAnimator, MovesTheFractionOfDistinctLightsWithinReach) {
  const auto start = randomLights(997, 5);
  for (const double fraction : {0.01, 0.1, 0.5, 1.0}) {
    const double speed = 0.3;
    LightAnimator anim(start, fraction, 7, speed);
    const std::size_t want = std::size_t(std::llround(fraction * 997.0));
    EXPECT_EQ(anim.movesPerStep(), want);
    auto before = start;
    for (int s = 0; s < 12; ++s) {
      const auto& now = anim.step();
      ASSERT_EQ(now.size(), start.size());
      const std::set<std::size_t> moved(anim.lastMoved().begin(), anim.lastMoved().end());
      EXPECT_EQ(moved.size(), want) << "moved indices must be distinct";
      std::size_t changed = 0;
      for (std::size_t i = 0; i < now.size(); ++i) {
        const auto& p = now[i].position_radius;
        const auto& q = before[i].position_radius;
        const bool differs = p.x != q.x || p.y != q.y || p.z != q.z;
        changed += differs;
        if (!moved.count(i)) {
          EXPECT_FALSE(differs) << "light " << i << " was not chosen but moved";
        }
        EXPECT_EQ(p.w, start[i].position_radius.w);
        const float reach = float(2 * speed) * p.w * 1.0001f;
        EXPECT_LE(std::abs(p.x - start[i].position_radius.x), reach);
        EXPECT_LE(std::abs(p.y - start[i].position_radius.y), reach);
        EXPECT_LE(std::abs(p.z - start[i].position_radius.z), reach);
      }
      EXPECT_GE(changed + 2, want);  // a clamped move can leave a light in place; rare
      before = now;
    }
  }
}

TEST(LightAnimator, DeterministicPerSeed) {
  const auto start = randomLights(200, 9);
  LightAnimator a(start, 0.1, 3), b(start, 0.1, 3), c(start, 0.1, 4);
  for (int s = 0; s < 5; ++s) {
    a.step();
    b.step();
    c.step();
  }
  bool same_ab = true, same_ac = true;
  for (std::size_t i = 0; i < start.size(); ++i) {
    same_ab &= a.lights()[i].position_radius.x == b.lights()[i].position_radius.x;
    same_ac &= a.lights()[i].position_radius.x == c.lights()[i].position_radius.x;
  }
  EXPECT_TRUE(same_ab);
  EXPECT_FALSE(same_ac);
}

TEST(LightAnimator, RejectsBadParameters) {
  auto msg = [](double f, double s) {
    try {
      LightAnimator({}, f, 23, s);
    } catch (const UserError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_NE(msg(-0.1, 0.25).find("--animate"), std::string::npos);
  EXPECT_NE(msg(1.5, 0.25).find("--animate"), std::string::npos);
  EXPECT_NE(msg(std::nan(""), 0.25).find("--animate"), std::string::npos);
  EXPECT_NE(msg(0.5, 0.0).find("--animate-speed"), std::string::npos);
  EXPECT_NE(msg(0.5, INFINITY).find("--animate-speed"), std::string::npos);
  EXPECT_EQ(msg(0.0, 0.25), "");
  EXPECT_EQ(LightAnimator({}, 1.0).movesPerStep(), 0u);
}

}  // namespace
}  // namespace ml
