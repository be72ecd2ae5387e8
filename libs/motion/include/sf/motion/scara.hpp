// SCARA arm kinematics (selective compliance articulated robot arm): two
// revolute joints in the horizontal plane (shoulder θ1, elbow θ2), a
// prismatic vertical axis (z) and a revolute wrist (θ4). Joint vector
// {θ1, θ2, z, θ4}; z is the tool point's height above the arm's base.
//
// Forward: p = base + l1·(cos θ1, sin θ1) + l2·(cos(θ1+θ2), sin(θ1+θ2)),
//          yaw = θ1 + θ2 + θ4.
// Inverse (law of cosines): cos θ2 = (r² − l1² − l2²) / (2·l1·l2); the sign
// of sin θ2 picks the elbow configuration (right-handed: θ2 > 0 is "left").
//
// θ1 and θ4 are revolute and may have a range wider than one turn, so an
// angle found by atan2 is only known modulo 2π; the `near` forms pick the
// turn closest to where the arm is, so a move never spins a joint by a turn
// to reach an angle it is next to.
#pragma once

#include <array>
#include <string>

#include "sf/core/result.hpp"
#include "sf/motion/geometry.hpp"

namespace sf::motion {

enum class Elbow { left, right };  // sign of θ2: left = positive (counter-clockwise)

inline constexpr std::array<const char*, 4> kScaraJointNames{"θ1", "θ2", "z", "θ4"};

struct JointLimit {
  double min = -std::numbers::pi;
  double max = std::numbers::pi;
  // With a nanometre's (nanoradian's) slack: a pose computed from joints at
  // a limit comes back a rounding error past it.
  [[nodiscard]] bool contains(double v) const { return v >= min - kSlack && v <= max + kSlack; }
  static constexpr double kSlack = 1e-9;
};

struct ScaraGeometry {
  Vec3 base;         // the shoulder axis on the floor plane, z of the z axis' zero
  double l1 = 0.25;  // shoulder → elbow (m)
  double l2 = 0.20;  // elbow → tool axis (m)
  std::array<JointLimit, 4> limits{
      {{-2.6, 2.6}, {-2.5, 2.5}, {0.0, 0.30}, {-std::numbers::pi, std::numbers::pi}}};
  // Radius around the shoulder axis inside which the arm is singular (θ1
  // undefined when l1 = l2) or cannot reach (|l1 − l2|).
  [[nodiscard]] double min_reach() const;
  [[nodiscard]] double max_reach() const { return l1 + l2; }
};

using ScaraJoints = std::array<double, 4>;  // θ1, θ2, z, θ4

// The configuration the joints are in; θ2 = 0 (full stretch) counts as left.
inline Elbow elbow_of(const ScaraJoints& q) {
  return q[1] >= 0.0 ? Elbow::left : Elbow::right;
}
const char* to_string(Elbow elbow);

// An error naming the first joint outside its limits.
Status check_joint_limits(const ScaraGeometry& g, const ScaraJoints& q);

ToolPose scara_forward(const ScaraGeometry& g, const ScaraJoints& q);

// Joints that put the tool at `pose` with the given elbow; errors: out of
// reach (naming the distance and the reach), singular, or a joint limit.
Result<ScaraJoints> scara_inverse(const ScaraGeometry& g, const ToolPose& pose, Elbow elbow);
// The same with θ1 and θ4 on the turn, among those within limits, closest to
// `near`: the target of a move that starts at `near`.
Result<ScaraJoints> scara_inverse(const ScaraGeometry& g, const ToolPose& pose, Elbow elbow,
                                  const ScaraJoints& near);
// The configuration of the two that is within limits and closest to
// `current` (sum of absolute joint moves, θ1 and θ4 unwrapped near it);
// error if neither is.
Result<ScaraJoints> scara_inverse_nearest(const ScaraGeometry& g, const ToolPose& pose,
                                          const ScaraJoints& current);
// Following a planned path cycle by cycle: the given elbow, θ1 and θ4 on the
// turn nearest the previous set-point even past a limit (the planner checked
// the limits; jumping a turn to stay inside one would be a step of 2π).
// Errors only when the pose is out of reach.
Result<ScaraJoints> scara_inverse_along(const ScaraGeometry& g, const ToolPose& pose, Elbow elbow,
                                        const ScaraJoints& previous);

// True when the horizontal point is in the arm's annulus and z within the
// z axis' stroke (limits not checked for the revolute joints).
bool scara_reaches(const ScaraGeometry& g, const Vec3& point);

}  // namespace sf::motion
