// Cartesian moves of the tool: straight lines through way-points, blended at
// corners without stopping.
//
// Each segment is a straight line in (x, y, z, yaw) with its own path
// parameter u ∈ [0, 1] following a jerk-limited rest-to-rest profile u(t)
// (jerk_profile.hpp); the tool pose is from + u·(to − from), solved for the
// joints every cycle in the elbow the path started in, so the tool is on the
// line at every set-point and the arm never flips its elbow mid-path.
//
// Limits along a line: the tool's own limits give u the bounds v/L, a/L,
// j/L. The joints follow q(u) with derivatives q', q'', q''' (differential
// kinematics, scara_differential.hpp), so in time
//   q̇ = q'·u̇,  q̈ = q''·u̇² + q'·ü,  q⃛ = q'''·u̇³ + 3·q''·u̇·ü + q'·u⃛.
// The planner samples q', q'', q''' along the line (and at its closest
// approach to the shoulder axis, where they peak) and lowers u's bounds until
// every axis stays within its limits: a line that passes near a singularity
// is slowed down, one that comes closer than the singularity margin is
// refused.
//
// Blending: a way-point with a blend radius R lets the next segment start
// while the current one is still decelerating, once the current one has R
// left to go; the tool moves on the sum of both lines' motions, so velocity
// and acceleration stay continuous and jerk bounded, the tool never strays
// further than R from the corner's two lines, and it passes the corner
// without stopping. Both lines' jerk phases add up in the overlap, so lines
// that blend are planned with half the jerk limits. The planner checks the
// axis and tool limits over each overlap and shortens it (down to a stop)
// where the sum would exceed them.
// R is capped at half of either adjacent segment, so at most two segments
// move the tool at any time.
//
// Start times and durations are whole cycles: the path ends exactly at its
// last way-point, at rest, on a cycle.
#pragma once

#include <cstddef>
#include <span>
#include <vector>

#include "sf/core/result.hpp"
#include "sf/motion/axis_limits.hpp"
#include "sf/motion/jerk_profile.hpp"
#include "sf/motion/scara.hpp"
#include "sf/motion/scara_differential.hpp"

namespace sf::motion {

struct Waypoint {
  ToolPose pose;
  double blend_radius = 0.0;  // m; 0: the tool stops exactly at the way-point
  double dwell = 0.0;         // s to stay at a stop before going on (e.g. for the gripper)
};

struct PathSegment {
  ToolPose from;
  Vec3 delta;                // to − from, m
  double yaw_delta = 0.0;    // the shorter way round, rad
  double length = 0.0;       // |delta|, m
  JerkProfile profile;       // u from 0 to 1
  double start = 0.0;        // s after the path's start
  double blend = 0.0;        // radius blended into the next segment (0: stops at its end)
  double dwell = 0.0;        // s at rest after its end when it stops there
  std::size_t waypoint = 0;  // index of the way-point it ends at
  ScaraJoints end_joints{};  // the arm at its end
  [[nodiscard]] double end() const { return start + profile.duration(); }
  [[nodiscard]] ToolPose at(double u) const;
};

class CartesianPath {
 public:
  // Where sampling has got to: lets a cycle-by-cycle reader skip finished
  // segments instead of searching.
  struct Cursor {
    std::size_t segment = 0;
  };

  [[nodiscard]] double duration() const { return static_cast<double>(cycles_) * cycle_; }
  [[nodiscard]] double cycle() const { return cycle_; }
  [[nodiscard]] std::size_t cycles() const { return cycles_; }
  [[nodiscard]] Elbow elbow() const { return elbow_; }
  [[nodiscard]] const ScaraJoints& start_joints() const { return start_; }
  [[nodiscard]] const ScaraJoints& end_joints() const { return end_; }
  [[nodiscard]] std::span<const PathSegment> segments() const { return segments_; }
  // When the tool reaches way-point i (for a blended way-point: when its
  // line would have reached it; the tool passes within the blend radius).
  [[nodiscard]] double arrival(std::size_t waypoint) const { return arrivals_.at(waypoint); }

  [[nodiscard]] ToolPose pose_at(double t) const;
  [[nodiscard]] ToolPose pose_at(double t, Cursor& cursor) const;
  // Time derivatives of the pose at t.
  [[nodiscard]] PoseDerivatives derivatives_at(double t) const;
  // The joints at t, continuous with `previous` (the set-point before).
  [[nodiscard]] Result<ScaraJoints> joints_at(double t, const ScaraJoints& previous, Cursor& cursor) const;
  // The set-point of cycle k (1 … cycles()) given the one of cycle k − 1.
  [[nodiscard]] Result<ScaraJoints> setpoint(std::size_t k, const ScaraJoints& previous,
                                             Cursor& cursor) const;

 private:
  friend Result<CartesianPath> plan_path(const ScaraGeometry&, const MotionLimits&, const ScaraJoints&,
                                         std::span<const Waypoint>);
  ScaraGeometry geometry_;
  Elbow elbow_ = Elbow::left;
  ScaraJoints start_{};
  ScaraJoints end_{};
  std::vector<PathSegment> segments_;
  std::vector<double> arrivals_;
  double cycle_ = kDefaultCycle;
  std::size_t cycles_ = 0;
};

// From the arm at joints `start` through `waypoints` in order, in the elbow
// of `start`. Errors name the way-point or segment and the cause: out of
// reach, needs the other elbow, a joint limit, too close to a singularity.
Result<CartesianPath> plan_path(const ScaraGeometry& g, const MotionLimits& limits, const ScaraJoints& start,
                                std::span<const Waypoint> waypoints);
// One straight line to `target`.
Result<CartesianPath> plan_line(const ScaraGeometry& g, const MotionLimits& limits, const ScaraJoints& start,
                                const ToolPose& target);

}  // namespace sf::motion
