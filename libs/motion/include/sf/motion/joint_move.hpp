// A point-to-point move in joint space, synchronised: each axis gets its own
// jerk-limited profile (jerk_profile.hpp), the slowest sets the duration and
// the others are slowed by time scaling to the same duration, so every axis
// starts and stops on the same cycle. The duration is rounded up to whole
// cycles, so the last set-point is the target exactly and at rest.
#pragma once

#include <array>
#include <cstddef>

#include "sf/core/result.hpp"
#include "sf/motion/axis_limits.hpp"
#include "sf/motion/jerk_profile.hpp"
#include "sf/motion/scara.hpp"

namespace sf::motion {

struct JointState {
  ScaraJoints position{};
  ScaraJoints velocity{};
  ScaraJoints acceleration{};
};

class JointMove {
 public:
  [[nodiscard]] const ScaraJoints& from() const { return from_; }
  [[nodiscard]] const ScaraJoints& to() const { return to_; }
  [[nodiscard]] double duration() const { return static_cast<double>(cycles_) * cycle_; }
  [[nodiscard]] double cycle() const { return cycle_; }
  [[nodiscard]] std::size_t cycles() const { return cycles_; }
  // The axis whose own fastest profile set the duration.
  [[nodiscard]] std::size_t leading_axis() const { return leading_; }
  [[nodiscard]] const JerkProfile& axis(std::size_t i) const { return axes_.at(i); }

  [[nodiscard]] JointState at(double t) const;
  // The set-point of cycle k (1 … cycles()); cycle 0 is `from`.
  [[nodiscard]] ScaraJoints setpoint(std::size_t k) const;

 private:
  friend Result<JointMove> plan_joint_move(const ScaraGeometry&, const MotionLimits&, const ScaraJoints&,
                                           const ScaraJoints&);
  ScaraJoints from_{};
  ScaraJoints to_{};
  std::array<JerkProfile, 4> axes_{};
  double cycle_ = kDefaultCycle;
  std::size_t cycles_ = 0;
  std::size_t leading_ = 0;
};

// From joints `from` to joints `to` (within the geometry's joint limits).
Result<JointMove> plan_joint_move(const ScaraGeometry& g, const MotionLimits& limits, const ScaraJoints& from,
                                  const ScaraJoints& to);
// To a tool pose, in the configuration of the two nearest `from`
// (scara_inverse_nearest), or in the given elbow.
Result<JointMove> plan_joint_move_to(const ScaraGeometry& g, const MotionLimits& limits,
                                     const ScaraJoints& from, const ToolPose& target);
Result<JointMove> plan_joint_move_to(const ScaraGeometry& g, const MotionLimits& limits,
                                     const ScaraJoints& from, const ToolPose& target, Elbow elbow);

}  // namespace sf::motion
