#include "sf/motion/jerk_profile.hpp"

#include <algorithm>
#include <cmath>

namespace sf::motion {

namespace {

// Jerk of each phase, in units of the profile's signed jerk.
constexpr std::array<double, 7> kPhaseJerk{1.0, 0.0, -1.0, 0.0, -1.0, 0.0, 1.0};

ProfileState advance(const ProfileState& s, double jerk, double dt) {
  return {s.position + dt * (s.velocity + dt * (s.acceleration / 2.0 + dt * jerk / 6.0)),
          s.velocity + dt * (s.acceleration + dt * jerk / 2.0), s.acceleration + dt * jerk, jerk};
}

}  // namespace

JerkProfile::JerkProfile(double distance, double tj, double ta, double tv, double jerk)
    : distance_(distance), tj_(tj), ta_(ta), tv_(tv), jerk_(jerk) {
  const std::array<double, 7> span{tj, ta, tj, tv, tj, ta, tj};
  ProfileState s;
  double t = 0.0;
  for (std::size_t i = 0; i < span.size(); ++i) {
    s.jerk = kPhaseJerk[i] * jerk;
    phase_[i] = s;
    t += span[i];
    phase_end_[i] = t;
    s = advance(s, s.jerk, span[i]);
  }
}

JerkProfile JerkProfile::fastest(double distance, const AxisLimit& limit) {
  const double d = std::abs(distance);
  if (d == 0.0) {
    return {};
  }
  const double v = limit.velocity;
  const double a = limit.acceleration;
  const double j = limit.jerk;
  const double sign = distance < 0.0 ? -1.0 : 1.0;
  // Case 1: the cruise velocity is reached. Accelerating to v takes
  // tj = a/j with a constant-acceleration phase, or tj = √(v/j) without one
  // when v·j < a² (a is never reached).
  double tj = v * j < a * a ? std::sqrt(v / j) : a / j;
  double ta = v * j < a * a ? 0.0 : v / a - tj;
  const double ramp = v * (2.0 * tj + ta);  // distance to reach v and leave it again
  if (d >= ramp) {
    return {distance, tj, ta, d / v - (2.0 * tj + ta), sign * j};
  }
  // Case 2: v is not reached but a is: d = a·(tj + ta)·(2·tj + ta) with
  // tj = a/j, a quadratic in ta.
  tj = a / j;
  ta = (-3.0 * tj + std::sqrt(tj * tj + 4.0 * d / a)) / 2.0;
  if (ta >= 0.0) {
    return {distance, tj, ta, 0.0, sign * j};
  }
  // Case 3: neither: d = 2·j·tj³.
  return {distance, std::cbrt(d / (2.0 * j)), 0.0, 0.0, sign * j};
}

JerkProfile JerkProfile::stretched(double duration) const {
  if (distance_ == 0.0) {
    return {0.0, 0.0, 0.0, std::max(duration, 0.0), 0.0};
  }
  const double k = std::max(duration / this->duration(), 1.0);
  return {distance_, tj_ * k, ta_ * k, tv_ * k, jerk_ / (k * k * k)};
}

double JerkProfile::peak_jerk() const {
  return std::abs(jerk_);
}

double JerkProfile::peak_acceleration() const {
  return std::abs(jerk_) * tj_;
}

double JerkProfile::peak_velocity() const {
  return std::abs(jerk_) * tj_ * (tj_ + ta_);
}

ProfileState JerkProfile::at(double t) const {
  if (t <= 0.0) {
    return {};
  }
  if (t >= duration()) {
    return {distance_, 0.0, 0.0, 0.0};
  }
  const auto i = static_cast<std::size_t>(std::upper_bound(phase_end_.begin(), phase_end_.end(), t) -
                                          phase_end_.begin());
  const double begin = i == 0 ? 0.0 : phase_end_[i - 1];
  return advance(phase_[i], phase_[i].jerk, t - begin);
}

double JerkProfile::time_at(double position) const {
  // Position is monotone in time; bisection to well below a cycle.
  double lo = 0.0;
  double hi = duration();
  const double target = std::abs(position);
  for (int i = 0; i < 60 && hi - lo > 1e-12; ++i) {
    const double mid = (lo + hi) / 2.0;
    (std::abs(at(mid).position) < target ? lo : hi) = mid;
  }
  return hi;
}

}  // namespace sf::motion
