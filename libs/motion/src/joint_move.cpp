#include "sf/motion/joint_move.hpp"

#include <cmath>

#include <fmt/format.h>

#include "cycles.hpp"

namespace sf::motion {

JointState JointMove::at(double t) const {
  JointState s;
  for (std::size_t i = 0; i < axes_.size(); ++i) {
    const ProfileState p = axes_[i].at(t);
    s.position[i] = t >= duration() ? to_[i] : from_[i] + p.position;
    s.velocity[i] = p.velocity;
    s.acceleration[i] = p.acceleration;
  }
  return s;
}

ScaraJoints JointMove::setpoint(std::size_t k) const {
  if (k >= cycles_) {
    return to_;
  }
  const double t = static_cast<double>(k) * cycle_;
  ScaraJoints q{};
  for (std::size_t i = 0; i < axes_.size(); ++i) {
    q[i] = from_[i] + axes_[i].at(t).position;
  }
  return q;
}

Result<JointMove> plan_joint_move(const ScaraGeometry& g, const MotionLimits& limits, const ScaraJoints& from,
                                  const ScaraJoints& to) {
  SF_TRY(validate(limits));
  for (std::size_t i = 0; i < from.size(); ++i) {
    if (!std::isfinite(from[i])) {
      return make_error(Errc::invalid_argument,
                        fmt::format("start joint {} is not a number", kScaraJointNames[i]));
    }
  }
  SF_TRY(check_joint_limits(g, to));
  JointMove m;
  m.from_ = from;
  m.to_ = to;
  m.cycle_ = limits.cycle;
  double slowest = 0.0;
  for (std::size_t i = 0; i < m.axes_.size(); ++i) {
    m.axes_[i] = JerkProfile::fastest(to[i] - from[i], limits.axes[i]);
    if (m.axes_[i].duration() > slowest) {
      slowest = m.axes_[i].duration();
      m.leading_ = i;
    }
  }
  m.cycles_ = detail::whole_cycles(slowest, limits.cycle);
  for (auto& axis : m.axes_) {
    axis = axis.stretched(m.duration());
  }
  return m;
}

Result<JointMove> plan_joint_move_to(const ScaraGeometry& g, const MotionLimits& limits,
                                     const ScaraJoints& from, const ToolPose& target) {
  auto to = scara_inverse_nearest(g, target, from);
  if (!to) {
    return to.error();
  }
  return plan_joint_move(g, limits, from, *to);
}

Result<JointMove> plan_joint_move_to(const ScaraGeometry& g, const MotionLimits& limits,
                                     const ScaraJoints& from, const ToolPose& target, Elbow elbow) {
  auto to = scara_inverse(g, target, elbow, from);
  if (!to) {
    return to.error();
  }
  return plan_joint_move(g, limits, from, *to);
}

}  // namespace sf::motion
