// What a planned move must respect: per-axis velocity, acceleration and jerk
// in joint units (rad or m per s, s², s³), the tool's limits for Cartesian
// moves, the controller's cycle and how close a Cartesian path may come to a
// singular arm configuration.
#pragma once

#include <array>

#include "sf/core/result.hpp"

namespace sf::motion {

struct AxisLimit {
  double velocity = 1.0;
  double acceleration = 10.0;
  double jerk = 200.0;
};

// θ1, θ2, z, θ4 (scara.hpp). The defaults stay well inside what the smart
// robot's drives follow in CSP (1e6 counts/s, 2e7 counts/s² at 1e5 counts/rad
// and 1e6 counts/m: 10 rad/s, 200 rad/s², 1 m/s, 20 m/s²), so the following
// error stays far below its window.
using AxisLimits = std::array<AxisLimit, 4>;

// Jerk: acceleration builds up in 20 ms.
inline constexpr AxisLimits kScaraAxisLimits{{
    {6.0, 40.0, 2000.0},   // θ1 shoulder: carries the whole arm
    {8.0, 60.0, 3000.0},   // θ2 elbow
    {0.8, 8.0, 400.0},     // z
    {10.0, 80.0, 4000.0},  // θ4 wrist
}};

// Limits of the tool point (linear, m) and of its yaw (rad) on Cartesian
// paths, on top of the axis limits.
struct ToolLimits {
  AxisLimit linear{1.5, 15.0, 750.0};
  AxisLimit yaw{6.0, 60.0, 3000.0};
};

// The EtherCAT cycle the set-points are sampled at (CSP: one target per axis
// per cycle).
inline constexpr double kDefaultCycle = 1e-3;

struct MotionLimits {
  AxisLimits axes = kScaraAxisLimits;
  ToolLimits tool;
  double cycle = kDefaultCycle;  // s
  // Smallest |sin θ2| a Cartesian path may pass through. The arm's Jacobian
  // has determinant l1·l2·sin θ2: it vanishes at full stretch (θ2 = 0) and
  // fully folded (θ2 = ±π, the inner radius), where joint speeds for a given
  // tool speed grow without bound.
  double singularity_margin = 0.1;
};

// Every limit positive and finite, the cycle positive, the margin in [0, 1).
Status validate(const MotionLimits& limits);

}  // namespace sf::motion
