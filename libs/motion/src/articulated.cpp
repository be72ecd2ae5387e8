#include "sf/motion/articulated.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

namespace sf::motion {

namespace {

constexpr double kHalfPi = std::numbers::pi / 2.0;
constexpr double kWristSingularRadius = 1e-3;  // wrist centre on the base axis: θ1 undefined

struct WristTarget {
  double r;  // horizontal distance of the wrist centre from the base axis
  double s;  // height of the wrist centre above the shoulder axis
};

WristTarget wrist_target(const ArticulatedGeometry& g, const Vec3& tool) {
  return {std::hypot(tool.x - g.base.x, tool.y - g.base.y), tool.z + g.tool - (g.base.z + g.shoulder)};
}

}  // namespace

ToolPose articulated_forward(const ArticulatedGeometry& g, const ArticulatedJoints& q) {
  const double reach = g.upper * std::cos(q[1]) + g.fore * std::cos(q[1] + q[2]);
  const double height = g.upper * std::sin(q[1]) + g.fore * std::sin(q[1] + q[2]);
  const double pitch = q[1] + q[2] + q[4];  // of the tool, −π/2 = straight down
  const double r = reach + g.tool * std::cos(pitch);
  const double z = g.base.z + g.shoulder + height + g.tool * std::sin(pitch);
  return ToolPose{{g.base.x + r * std::cos(q[0]), g.base.y + r * std::sin(q[0]), z}, wrap_angle(q[0] + q[5])};
}

Result<ArticulatedJoints> articulated_inverse(const ArticulatedGeometry& g, const ToolPose& pose) {
  const auto [r, s] = wrist_target(g, pose.position);
  if (r < kWristSingularRadius) {
    return make_error(Errc::out_of_range, "wrist centre on the base axis (singular)");
  }
  const double d = std::hypot(r, s);
  if (d > g.upper + g.fore || d < std::abs(g.upper - g.fore)) {
    return make_error(Errc::out_of_range,
                      fmt::format("wrist centre {:.4f} m from the shoulder, outside [{:.4f}, {:.4f}] m", d,
                                  std::abs(g.upper - g.fore), g.upper + g.fore));
  }
  const double c3 =
      std::clamp((d * d - g.upper * g.upper - g.fore * g.fore) / (2.0 * g.upper * g.fore), -1.0, 1.0);
  const double q3 = -std::acos(c3);  // elbow up: the forearm folds down from the upper arm
  const double q2 = std::atan2(s, r) - std::atan2(g.fore * std::sin(q3), g.upper + g.fore * std::cos(q3));
  const double q1 = std::atan2(pose.position.y - g.base.y, pose.position.x - g.base.x);
  const double q5 = -kHalfPi - q2 - q3;
  const double q6 = wrap_angle(pose.yaw - q1);
  ArticulatedJoints q{q1, q2, q3, 0.0, q5, q6};
  for (std::size_t i = 0; i < q.size(); ++i) {
    if (!g.limits[i].contains(q[i])) {
      return make_error(Errc::out_of_range,
                        fmt::format("joint {} = {:.4f} outside its limits [{:.4f}, {:.4f}]", i + 1, q[i],
                                    g.limits[i].min, g.limits[i].max));
    }
  }
  return q;
}

bool articulated_reaches(const ArticulatedGeometry& g, const Vec3& point) {
  return articulated_inverse(g, ToolPose{point, 0.0}).ok();
}

}  // namespace sf::motion
