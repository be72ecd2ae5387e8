// Differential kinematics of the SCARA arm (scara.hpp): how fast the joints
// turn when the tool moves, and where that breaks down.
//
// With σ = θ1 + θ2, e(a) = (cos a, sin a) and n(a) = (−sin a, cos a), the
// tool's horizontal point is p = l1·e(θ1) + l2·e(σ). Differentiating,
//
//   p'   = M·(θ1', σ')                                  M = [l1·n(θ1) | l2·n(σ)]
//   p''  = M·(θ1'', σ'')  − l1·θ1'²·e(θ1) − l2·σ'²·e(σ)
//   p''' = M·(θ1''', σ''') − 3·l1·θ1'·θ1''·e(θ1) − l1·θ1'³·n(θ1) − (same in σ)
//
// and det M = l1·l2·sin θ2: the Jacobian is singular at full stretch
// (θ2 = 0, the outer edge of the workspace) and fully folded (θ2 = ±π, the
// inner radius). Near them a modest tool speed needs joint speeds that grow
// like 1/|sin θ2|, so Cartesian paths keep |sin θ2| above a margin.
// z and yaw are decoupled: z' = p_z', θ4 = yaw − σ.
#pragma once

#include <array>

#include "sf/core/result.hpp"
#include "sf/motion/scara.hpp"

namespace sf::motion {

// First three derivatives of the tool pose (x, y, z, yaw) with respect to
// time or to a path parameter.
struct PoseDerivatives {
  std::array<double, 4> first{};
  std::array<double, 4> second{};
  std::array<double, 4> third{};
};

struct JointDerivatives {
  ScaraJoints first{};
  ScaraJoints second{};
  ScaraJoints third{};
};

// The joints' derivatives at joints q while the tool's pose has derivatives
// p. Needs sin θ2 ≠ 0 (check_singularity).
JointDerivatives scara_joint_derivatives(const ScaraGeometry& g, const ScaraJoints& q,
                                         const PoseDerivatives& p);

// |sin θ2|: 1 with the links at a right angle, 0 at the singularities.
double scara_conditioning(const ScaraJoints& q);

// An error when |sin θ2| < margin, naming which singularity (full stretch or
// the folded arm at the inner radius) and how far from the shoulder axis.
Status check_singularity(const ScaraGeometry& g, const ScaraJoints& q, double margin);

}  // namespace sf::motion
