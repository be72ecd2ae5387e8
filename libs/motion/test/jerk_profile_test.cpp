#include "sf/motion/jerk_profile.hpp"

#include <cmath>

#include <gtest/gtest.h>

namespace sf::motion {
namespace {

constexpr AxisLimit kLimit{2.0, 10.0, 100.0};  // tj = A/J = 0.1 s, V/A = 0.2 s

// Samples the profile densely: it ends at its distance, moves one way only,
// and its velocity, acceleration and jerk stay within `limit`; its velocity
// and acceleration are the derivatives of its position and velocity.
void expect_consistent(const JerkProfile& p, const AxisLimit& limit) {
  const double dt = p.duration() / 4000.0;
  double last = 0.0;
  for (int i = 0; i <= 4000; ++i) {
    const double t = i * dt;
    const ProfileState s = p.at(t);
    EXPECT_LE(std::abs(s.velocity), limit.velocity * (1 + 1e-9));
    EXPECT_LE(std::abs(s.acceleration), limit.acceleration * (1 + 1e-9));
    EXPECT_LE(std::abs(s.jerk), limit.jerk * (1 + 1e-9));
    EXPECT_GE(s.position * std::copysign(1.0, p.distance()) + 1e-12, last * std::copysign(1.0, p.distance()));
    last = s.position;
    if (i > 0 && i < 4000) {
      const ProfileState a = p.at(t - dt / 10);
      const ProfileState b = p.at(t + dt / 10);
      EXPECT_NEAR((b.position - a.position) / (dt / 5), s.velocity, 1e-4);
      EXPECT_NEAR((b.velocity - a.velocity) / (dt / 5), s.acceleration, 1e-2);
    }
  }
  EXPECT_DOUBLE_EQ(p.at(p.duration()).position, p.distance());
  EXPECT_NEAR(p.at(p.duration() * (1 - 1e-12)).position, p.distance(), 1e-9);
}

// Long enough to cruise: tj = 0.1, ta = 0.1, the ramps cover V·(2tj + ta) =
// 0.6, so 1.0 cruises for 0.4 / 2 = 0.2 s; T = 4tj + 2ta + tv = 0.8 s.
TEST(JerkProfileTest, CruisesWhenTheDistanceAllows) {
  const auto p = JerkProfile::fastest(1.0, kLimit);
  EXPECT_NEAR(p.jerk_time(), 0.1, 1e-12);
  EXPECT_NEAR(p.acceleration_time(), 0.1, 1e-12);
  EXPECT_NEAR(p.cruise_time(), 0.2, 1e-12);
  EXPECT_NEAR(p.duration(), 0.8, 1e-12);
  EXPECT_NEAR(p.peak_velocity(), 2.0, 1e-12);
  EXPECT_NEAR(p.peak_acceleration(), 10.0, 1e-12);
  EXPECT_NEAR(p.peak_jerk(), 100.0, 1e-12);
  EXPECT_NEAR(p.at(0.4).velocity, 2.0, 1e-12);
  EXPECT_NEAR(p.at(0.4).position, 0.5, 1e-12);  // symmetric: half way at half time
  expect_consistent(p, kLimit);
}

// Too short to cruise, long enough to hold A: d = A·(tj + ta)·(2tj + ta).
TEST(JerkProfileTest, HoldsTheAccelerationWithoutCruising) {
  const auto p = JerkProfile::fastest(0.3, kLimit);
  const double ta = (-0.3 + std::sqrt(0.01 + 4 * 0.3 / 10.0)) / 2;
  EXPECT_NEAR(p.jerk_time(), 0.1, 1e-12);
  EXPECT_NEAR(p.acceleration_time(), ta, 1e-12);
  EXPECT_EQ(p.cruise_time(), 0.0);
  EXPECT_NEAR(p.peak_acceleration(), 10.0, 1e-12);
  EXPECT_NEAR(p.peak_velocity(), 10.0 * (0.1 + ta), 1e-12);
  EXPECT_NEAR(10.0 * (0.1 + ta) * (0.2 + ta), 0.3, 1e-12);
  expect_consistent(p, kLimit);
}

// Shorter than 2·A³/J² = 0.2: jerk only, d = 2·J·tj³.
TEST(JerkProfileTest, PureJerkForShortMoves) {
  const auto p = JerkProfile::fastest(-0.01, kLimit);
  const double tj = std::cbrt(0.01 / 200.0);
  EXPECT_NEAR(p.jerk_time(), tj, 1e-12);
  EXPECT_EQ(p.acceleration_time(), 0.0);
  EXPECT_EQ(p.cruise_time(), 0.0);
  EXPECT_NEAR(p.duration(), 4 * tj, 1e-12);
  EXPECT_NEAR(p.peak_acceleration(), 100.0 * tj, 1e-12);
  EXPECT_NEAR(p.at(p.duration()).position, -0.01, 1e-15);
  EXPECT_LT(p.at(p.duration() / 2).velocity, 0.0);
  expect_consistent(p, kLimit);
}

// V·J < A²: the velocity is reached before the acceleration could be:
// tj = √(V/J), no constant-acceleration phase.
TEST(JerkProfileTest, VelocityReachedBeforeTheAcceleration) {
  const AxisLimit slow{0.5, 10.0, 100.0};
  const auto p = JerkProfile::fastest(1.0, slow);
  EXPECT_NEAR(p.jerk_time(), std::sqrt(0.005), 1e-12);
  EXPECT_EQ(p.acceleration_time(), 0.0);
  EXPECT_NEAR(p.peak_velocity(), 0.5, 1e-12);
  EXPECT_NEAR(p.cruise_time(), 1.0 / 0.5 - 2 * std::sqrt(0.005), 1e-12);
  expect_consistent(p, slow);
}

TEST(JerkProfileTest, StretchingScalesTimeAndThePeaks) {
  const auto fast = JerkProfile::fastest(1.0, kLimit);
  const auto slow = fast.stretched(1.6);
  EXPECT_NEAR(slow.duration(), 1.6, 1e-12);
  EXPECT_NEAR(slow.peak_velocity(), 1.0, 1e-12);
  EXPECT_NEAR(slow.peak_acceleration(), 2.5, 1e-12);
  EXPECT_NEAR(slow.peak_jerk(), 12.5, 1e-12);
  EXPECT_NEAR(slow.at(1.0).position, fast.at(0.5).position, 1e-12);
  expect_consistent(slow, kLimit);
  // Never faster than the fastest, and no motion stays no motion.
  EXPECT_NEAR(fast.stretched(0.1).duration(), 0.8, 1e-12);
  const auto still = JerkProfile::fastest(0.0, kLimit).stretched(0.5);
  EXPECT_EQ(still.duration(), 0.5);
  EXPECT_EQ(still.at(0.25).position, 0.0);
}

TEST(JerkProfileTest, TimeAtInvertsThePosition) {
  const auto p = JerkProfile::fastest(1.0, kLimit);
  for (double x : {0.0, 0.01, 0.3, 0.5, 0.9, 1.0}) {
    EXPECT_NEAR(p.at(p.time_at(x)).position, x, 1e-9);
  }
  EXPECT_NEAR(p.time_at(0.5), 0.4, 1e-9);
}

}  // namespace
}  // namespace sf::motion
