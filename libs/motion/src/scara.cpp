#include "sf/motion/scara.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include <fmt/format.h>

namespace sf::motion {

namespace {

// Closer than this to the shoulder axis θ1 is undefined (l1 = l2) or the
// Jacobian is too ill-conditioned to follow a path.
constexpr double kShoulderSingularRadius = 1e-3;
constexpr double kTurn = 2.0 * std::numbers::pi;

double moves(const ScaraJoints& a, const ScaraJoints& b) {
  double sum = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    sum += std::abs(a[i] - b[i]);
  }
  return sum;
}

// Law of cosines, angles wrapped into (−π, π], limits not checked.
Result<ScaraJoints> solve(const ScaraGeometry& g, const ToolPose& pose, Elbow elbow) {
  const double x = pose.position.x - g.base.x;
  const double y = pose.position.y - g.base.y;
  const double r = std::hypot(x, y);
  if (r > g.max_reach() + 1e-12) {
    return make_error(
        Errc::out_of_range,
        fmt::format("point {:.4f} m from the shoulder axis, beyond the reach {:.4f} m", r, g.max_reach()));
  }
  if (r < g.min_reach() - 1e-12) {
    return make_error(
        Errc::out_of_range,
        fmt::format("point {:.4f} m from the shoulder axis, inside the inner radius {:.4f} m the arm cannot "
                    "reach (θ1 is undefined on the axis)",
                    r, g.min_reach()));
  }
  const double c2 = std::clamp((r * r - g.l1 * g.l1 - g.l2 * g.l2) / (2.0 * g.l1 * g.l2), -1.0, 1.0);
  const double s2 = (elbow == Elbow::left ? 1.0 : -1.0) * std::sqrt(1.0 - c2 * c2);
  const double q2 = std::atan2(s2, c2);
  const double q1 = wrap_angle(std::atan2(y, x) - std::atan2(g.l2 * s2, g.l1 + g.l2 * c2));
  const double q4 = wrap_angle(pose.yaw - q1 - q2);
  return ScaraJoints{q1, q2, pose.position.z - g.base.z, q4};
}

// Of the turns of `a` next to `near` (one turn either way: joint ranges
// here are under two turns wide), the nearest within `limit`; the nearest
// of all when none is within (the limit check then names it).
double turn_within(double a, double near, const JointLimit& limit) {
  double best = unwrap_near(a, near);
  for (const double candidate : {best - kTurn, best + kTurn}) {
    if (limit.contains(candidate) &&
        (!limit.contains(best) || std::abs(candidate - near) < std::abs(best - near))) {
      best = candidate;
    }
  }
  return best;
}

}  // namespace

const char* to_string(Elbow elbow) {
  return elbow == Elbow::left ? "left" : "right";
}

Status check_joint_limits(const ScaraGeometry& g, const ScaraJoints& q) {
  for (std::size_t i = 0; i < q.size(); ++i) {
    if (!g.limits[i].contains(q[i])) {
      return make_error(Errc::out_of_range,
                        fmt::format("joint {} = {:.4f} outside its limits [{:.4f}, {:.4f}]",
                                    kScaraJointNames[i], q[i], g.limits[i].min, g.limits[i].max));
    }
  }
  return {};
}

double ScaraGeometry::min_reach() const {
  return std::max(std::abs(l1 - l2), kShoulderSingularRadius);
}

ToolPose scara_forward(const ScaraGeometry& g, const ScaraJoints& q) {
  const double a = q[0];
  const double b = q[0] + q[1];
  return ToolPose{{g.base.x + g.l1 * std::cos(a) + g.l2 * std::cos(b),
                   g.base.y + g.l1 * std::sin(a) + g.l2 * std::sin(b), g.base.z + q[2]},
                  wrap_angle(b + q[3])};
}

Result<ScaraJoints> scara_inverse(const ScaraGeometry& g, const ToolPose& pose, Elbow elbow) {
  auto q = solve(g, pose, elbow);
  if (q) {
    SF_TRY(check_joint_limits(g, *q));
  }
  return q;
}

Result<ScaraJoints> scara_inverse(const ScaraGeometry& g, const ToolPose& pose, Elbow elbow,
                                  const ScaraJoints& near) {
  auto q = solve(g, pose, elbow);
  if (q) {
    (*q)[0] = turn_within((*q)[0], near[0], g.limits[0]);
    (*q)[3] = turn_within((*q)[3], near[3], g.limits[3]);
    SF_TRY(check_joint_limits(g, *q));
  }
  return q;
}

Result<ScaraJoints> scara_inverse_nearest(const ScaraGeometry& g, const ToolPose& pose,
                                          const ScaraJoints& current) {
  auto left = scara_inverse(g, pose, Elbow::left, current);
  auto right = scara_inverse(g, pose, Elbow::right, current);
  if (left && right) {
    return moves(*left, current) <= moves(*right, current) ? left : right;
  }
  if (left) {
    return left;
  }
  if (right) {
    return right;
  }
  return left.error();
}

Result<ScaraJoints> scara_inverse_along(const ScaraGeometry& g, const ToolPose& pose, Elbow elbow,
                                        const ScaraJoints& previous) {
  auto q = solve(g, pose, elbow);
  if (q) {
    (*q)[0] = unwrap_near((*q)[0], previous[0]);
    (*q)[3] = unwrap_near((*q)[3], previous[3]);
  }
  return q;
}

bool scara_reaches(const ScaraGeometry& g, const Vec3& point) {
  const double r = std::hypot(point.x - g.base.x, point.y - g.base.y);
  const double z = point.z - g.base.z;
  return r >= g.min_reach() && r <= g.max_reach() && g.limits[2].contains(z);
}

}  // namespace sf::motion
