// SCARA arm kinematics (selective compliance articulated robot arm): two
// revolute joints in the horizontal plane (shoulder θ1, elbow θ2), a
// prismatic vertical axis (z) and a revolute wrist (θ4). Joint vector
// {θ1, θ2, z, θ4}; z is the tool point's height above the arm's base.
//
// Forward: p = base + l1·(cos θ1, sin θ1) + l2·(cos(θ1+θ2), sin(θ1+θ2)),
//          yaw = θ1 + θ2 + θ4.
// Inverse (law of cosines): cos θ2 = (r² − l1² − l2²) / (2·l1·l2); the sign
// of sin θ2 picks the elbow configuration (right-handed: θ2 > 0 is "left").
#pragma once

#include <array>
#include <string>

#include "sf/core/result.hpp"
#include "sf/motion/geometry.hpp"

namespace sf::motion {

enum class Elbow { left, right };  // sign of θ2: left = positive (counter-clockwise)

struct JointLimit {
  double min = -std::numbers::pi;
  double max = std::numbers::pi;
  [[nodiscard]] bool contains(double v) const { return v >= min && v <= max; }
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

ToolPose scara_forward(const ScaraGeometry& g, const ScaraJoints& q);

// Joints that put the tool at `pose` with the given elbow; errors: out of
// reach (naming the distance and the reach), singular, or a joint limit.
Result<ScaraJoints> scara_inverse(const ScaraGeometry& g, const ToolPose& pose, Elbow elbow);
// The configuration of the two that is within limits and closest to
// `current` (sum of absolute joint moves); error if neither is.
Result<ScaraJoints> scara_inverse_nearest(const ScaraGeometry& g, const ToolPose& pose,
                                          const ScaraJoints& current);

// True when the horizontal point is in the arm's annulus and z within the
// z axis' stroke (limits not checked for the revolute joints).
bool scara_reaches(const ScaraGeometry& g, const Vec3& point);

}  // namespace sf::motion
