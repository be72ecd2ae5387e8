// A jerk-limited rest-to-rest move of one axis: the 7-segment S-curve
// ("double S", Biagiotti & Melchiorri, Trajectory Planning for Automatic
// Machines and Robots, §3.4). Jerk is ±J or 0 in the phases
//
//   1 +J  (tj)   2 0 (ta)   3 −J (tj)   4 0 (tv, cruise)   5 −J (tj)   6 0 (ta)   7 +J (tj)
//
// so acceleration is a trapezoid up to A = J·tj and back, velocity an S up to
// V = A·(tj + ta), and distance = V·(2·tj + ta + tv). Bounded jerk keeps the
// motor torque from stepping, which is what excites a SCARA's links.
#pragma once

#include <array>

#include "sf/motion/axis_limits.hpp"

namespace sf::motion {

struct ProfileState {
  double position = 0.0;  // from the start of the move
  double velocity = 0.0;
  double acceleration = 0.0;
  double jerk = 0.0;
};

class JerkProfile {
 public:
  JerkProfile() = default;  // no motion, no duration

  // The minimum-time profile over `distance` (signed) within `limit`, whose
  // members must be positive. Closed form: V is reached if the distance
  // allows it, else A, else neither (a pure jerk profile).
  static JerkProfile fastest(double distance, const AxisLimit& limit);

  // The same profile slowed to `duration` (≥ duration()) by scaling time:
  // phases ×k, jerk ÷k³, so peak velocity, acceleration and jerk drop by k,
  // k², k³ and any limit the fast one met still holds. A zero-distance
  // profile just lasts longer.
  [[nodiscard]] JerkProfile stretched(double duration) const;

  [[nodiscard]] double duration() const { return phase_end_[6]; }
  [[nodiscard]] double distance() const { return distance_; }
  [[nodiscard]] double jerk_time() const { return tj_; }
  [[nodiscard]] double acceleration_time() const { return ta_; }
  [[nodiscard]] double cruise_time() const { return tv_; }
  [[nodiscard]] double peak_jerk() const;
  [[nodiscard]] double peak_acceleration() const;
  [[nodiscard]] double peak_velocity() const;

  // The state at time t (clamped to [0, duration()]; the end is exact).
  [[nodiscard]] ProfileState at(double t) const;
  // The first time the position reaches `position` (between 0 and distance()).
  [[nodiscard]] double time_at(double position) const;

 private:
  JerkProfile(double distance, double tj, double ta, double tv, double jerk);

  double distance_ = 0.0;
  double tj_ = 0.0;
  double ta_ = 0.0;
  double tv_ = 0.0;
  double jerk_ = 0.0;                    // signed: the direction of the move
  std::array<double, 7> phase_end_{};    // time at the end of each phase
  std::array<ProfileState, 7> phase_{};  // state at the start of each phase
};

}  // namespace sf::motion
