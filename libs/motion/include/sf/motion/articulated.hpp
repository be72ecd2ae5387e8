// Kinematics of a six-axis articulated arm whose tool points down, the way
// a pick-and-place cell uses it: base yaw θ1, shoulder pitch θ2 and elbow
// pitch θ3 place the wrist centre (a planar two-link problem in the arm's
// vertical plane), wrist pitch θ5 keeps the tool vertical, flange θ6 sets the
// tool's yaw, wrist roll θ4 stays 0 (a spherical wrist with the tool down
// needs no roll). Pitches are measured from the horizontal, up positive.
#pragma once

#include <array>

#include "sf/core/result.hpp"
#include "sf/motion/geometry.hpp"
#include "sf/motion/scara.hpp"

namespace sf::motion {

struct ArticulatedGeometry {
  Vec3 base;               // where the base stands
  double shoulder = 0.28;  // height of the shoulder axis above the base (m)
  double upper = 0.30;     // shoulder → elbow (m)
  double fore = 0.30;      // elbow → wrist centre (m)
  double tool = 0.08;      // wrist centre → tool point, along the tool (m)
  std::array<JointLimit, 6> limits{
      {{-2.9, 2.9}, {-1.9, 2.2}, {-2.8, 0.2}, {-3.1, 3.1}, {-2.1, 2.1}, {-6.2, 6.2}}};
};

using ArticulatedJoints = std::array<double, 6>;

ToolPose articulated_forward(const ArticulatedGeometry& g, const ArticulatedJoints& q);
// Elbow-up solution with the tool pointing down; errors name the cause.
Result<ArticulatedJoints> articulated_inverse(const ArticulatedGeometry& g, const ToolPose& pose);
bool articulated_reaches(const ArticulatedGeometry& g, const Vec3& point);

}  // namespace sf::motion
