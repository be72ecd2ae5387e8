#include "sf/motion/axis_limits.hpp"

#include <cmath>

#include <fmt/format.h>

#include "sf/motion/scara.hpp"

namespace sf::motion {

namespace {

bool positive(double v) {
  return std::isfinite(v) && v > 0.0;
}

Status check(const AxisLimit& l, const char* what) {
  if (!positive(l.velocity) || !positive(l.acceleration) || !positive(l.jerk)) {
    return make_error(Errc::invalid_argument,
                      fmt::format("{}: velocity {}, acceleration {} and jerk {} must be positive and finite",
                                  what, l.velocity, l.acceleration, l.jerk));
  }
  return {};
}

}  // namespace

Status validate(const MotionLimits& limits) {
  for (std::size_t i = 0; i < limits.axes.size(); ++i) {
    SF_TRY(check(limits.axes[i], kScaraJointNames[i]));
  }
  SF_TRY(check(limits.tool.linear, "tool"));
  SF_TRY(check(limits.tool.yaw, "tool yaw"));
  if (!positive(limits.cycle)) {
    return make_error(Errc::invalid_argument, fmt::format("cycle {} s must be positive", limits.cycle));
  }
  if (!(limits.singularity_margin >= 0.0 && limits.singularity_margin < 1.0)) {
    return make_error(Errc::invalid_argument,
                      fmt::format("singularity margin {} must be in [0, 1)", limits.singularity_margin));
  }
  return {};
}

}  // namespace sf::motion
