#include "sf/motion/cartesian_path.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "cycles.hpp"
#include "path_limits.hpp"

namespace sf::motion {

namespace {

// Shorter than this (m, rad) a segment does not move the tool.
constexpr double kNoMotion = 1e-9;

// The first segment not finished at t (or the last), searching from `first`.
std::size_t first_active(std::span<const PathSegment> segments, double t, std::size_t first) {
  while (first + 1 < segments.size() && segments[first].end() <= t) {
    ++first;
  }
  return first;
}

// Calls f(segment, its profile's state at t) for the segments from `first`
// that have started by t: at most two (cartesian_path.hpp).
template <typename F>
void for_active(std::span<const PathSegment> segments, double t, std::size_t first, F&& f) {
  for (std::size_t k = first; k < segments.size() && segments[k].start <= t; ++k) {
    f(segments[k], segments[k].profile.at(t - segments[k].start));
  }
}

Status check_waypoint(const ScaraGeometry& g, const Waypoint& w, Elbow elbow, const ScaraJoints& near) {
  const ToolPose& p = w.pose;
  if (!std::isfinite(p.position.x) || !std::isfinite(p.position.y) || !std::isfinite(p.position.z) ||
      !std::isfinite(p.yaw) || !(w.blend_radius >= 0.0) || !(w.dwell >= 0.0) ||
      !std::isfinite(w.blend_radius) || !std::isfinite(w.dwell)) {
    return make_error(Errc::invalid_argument,
                      "pose, blend radius and dwell must be finite, radius and dwell ≥ 0");
  }
  auto q = scara_inverse(g, p, elbow, near);
  if (q) {
    return {};
  }
  const Elbow other = elbow == Elbow::left ? Elbow::right : Elbow::left;
  if (scara_inverse(g, p, other, near)) {
    return make_error(
        Errc::out_of_range,
        fmt::format("reachable only with the {} elbow; a Cartesian path keeps the {} elbow it starts "
                    "in (a joint move changes the configuration)",
                    to_string(other), to_string(elbow)));
  }
  return q.error();
}

Error at_waypoint(const Error& e, std::size_t i) {
  return e.with_context(fmt::format("way-point {}", i));
}

Error on_line_to(const Error& e, std::size_t i) {
  return e.with_context(fmt::format("on the line to way-point {}", i));
}

// The limits with half the jerk. In a blend's overlap the jerk phases of
// both lines add up (the end of one and the start of the next), so a line
// that blends into a neighbour leaves half the jerk to it.
MotionLimits half_jerk(MotionLimits limits) {
  for (auto& axis : limits.axes) {
    axis.jerk /= 2.0;
  }
  limits.tool.linear.jerk /= 2.0;
  limits.tool.yaw.jerk /= 2.0;
  return limits;
}

bool blends_at(std::span<const Waypoint> waypoints, std::size_t i) {
  return i + 1 < waypoints.size() && waypoints[i].blend_radius > 0.0;
}

// The straight segments from `start` through the way-points (those that do
// not move the tool dropped), each with its fastest profile on whole cycles.
Status build_lines(const ScaraGeometry& g, const MotionLimits& limits, Elbow elbow, ScaraJoints& joints,
                   std::span<const Waypoint> waypoints, std::vector<PathSegment>& lines) {
  const MotionLimits blending = half_jerk(limits);
  ToolPose at = scara_forward(g, joints);
  for (std::size_t i = 0; i < waypoints.size(); ++i) {
    const Waypoint& w = waypoints[i];
    if (auto s = check_waypoint(g, w, elbow, joints); !s) {
      return at_waypoint(s.error(), i);
    }
    PathSegment line;
    line.from = at;
    line.delta = w.pose.position - at.position;
    line.yaw_delta = wrap_angle(w.pose.yaw - at.yaw);
    line.length = norm(line.delta);
    line.blend = w.blend_radius;
    line.dwell = w.blend_radius > 0.0 ? 0.0 : w.dwell;
    line.waypoint = i;
    if (line.length < kNoMotion && std::abs(line.yaw_delta) < kNoMotion) {
      if (!lines.empty() && w.blend_radius == 0.0) {
        lines.back().blend = 0.0;  // a repeated way-point without blending: stop at it
        lines.back().dwell += w.dwell;
      }
      continue;
    }
    const bool blends = blends_at(waypoints, i) || (i > 0 && blends_at(waypoints, i - 1));
    auto profile = detail::line_profile(g, blends ? blending : limits, elbow, line, joints);
    if (!profile) {
      return on_line_to(profile.error(), i);
    }
    line.profile = profile->stretched(
        static_cast<double>(detail::whole_cycles(profile->duration(), limits.cycle)) * limits.cycle);
    line.end_joints = joints;
    lines.push_back(line);
    at = {w.pose.position, at.yaw + line.yaw_delta};  // yaw stays continuous along the path
  }
  return {};
}

double on_grid(double t, double cycle) {
  return static_cast<double>(detail::whole_cycles(t, cycle)) * cycle;
}

// When segment k + 1 starts: at the end of k (plus its dwell) when k stops,
// else as early as the blend allows — once k has R left, after k − 1 has
// finished (two segments at most), and with the overlap within limits
// (later, by bisection over cycles, while it is not).
double next_start(const ScaraGeometry& g, const MotionLimits& limits, Elbow elbow,
                  std::span<const PathSegment> lines, std::size_t k) {
  const PathSegment& a = lines[k];
  const PathSegment& b = lines[k + 1];
  const double stop = on_grid(a.end() + a.dwell, limits.cycle);
  const double radius = std::min({a.blend, a.length / 2.0, b.length / 2.0});
  if (radius <= 0.0) {
    return stop;
  }
  double earliest = a.start + a.profile.time_at(1.0 - radius / a.length);
  if (k > 0) {
    earliest = std::max(earliest, lines[k - 1].end());
  }
  auto lo = static_cast<std::int64_t>(detail::whole_cycles(earliest, limits.cycle));
  auto hi = static_cast<std::int64_t>(detail::whole_cycles(a.end(), limits.cycle));
  const auto fits = [&](std::int64_t c) {
    return detail::overlap_within_limits(g, limits, elbow, a, b, static_cast<double>(c) * limits.cycle,
                                         a.end_joints);
  };
  if (lo >= hi || fits(lo)) {
    return static_cast<double>(std::min(lo, hi)) * limits.cycle;
  }
  while (hi - lo > 1) {  // fits(hi): at a's end both stand still
    const std::int64_t mid = (lo + hi) / 2;
    (fits(mid) ? hi : lo) = mid;
  }
  return static_cast<double>(hi) * limits.cycle;
}

}  // namespace

ToolPose PathSegment::at(double u) const {
  return {from.position + u * delta, from.yaw + u * yaw_delta};
}

ToolPose CartesianPath::pose_at(double t) const {
  Cursor cursor;
  return pose_at(t, cursor);
}

ToolPose CartesianPath::pose_at(double t, Cursor& cursor) const {
  if (segments_.empty()) {
    return scara_forward(geometry_, start_);
  }
  cursor.segment = first_active(segments_, t, cursor.segment);
  ToolPose pose = segments_[cursor.segment].from;
  for_active(segments_, t, cursor.segment, [&](const PathSegment& s, const ProfileState& u) {
    pose.position = pose.position + u.position * s.delta;
    pose.yaw += u.position * s.yaw_delta;
  });
  return pose;
}

PoseDerivatives CartesianPath::derivatives_at(double t) const {
  PoseDerivatives p;
  for_active(segments_, t, first_active(segments_, t, 0), [&](const PathSegment& s, const ProfileState& u) {
    const std::array<double, 4> d{s.delta.x, s.delta.y, s.delta.z, s.yaw_delta};
    for (std::size_t i = 0; i < d.size(); ++i) {
      p.first[i] += u.velocity * d[i];
      p.second[i] += u.acceleration * d[i];
      p.third[i] += u.jerk * d[i];
    }
  });
  return p;
}

Result<ScaraJoints> CartesianPath::joints_at(double t, const ScaraJoints& previous, Cursor& cursor) const {
  return scara_inverse_along(geometry_, pose_at(t, cursor), elbow_, previous);
}

Result<ScaraJoints> CartesianPath::setpoint(std::size_t k, const ScaraJoints& previous,
                                            Cursor& cursor) const {
  if (k >= cycles_) {
    return end_;
  }
  return joints_at(static_cast<double>(k) * cycle_, previous, cursor);
}

Result<CartesianPath> plan_path(const ScaraGeometry& g, const MotionLimits& limits, const ScaraJoints& start,
                                std::span<const Waypoint> waypoints) {
  SF_TRY(validate(limits));
  if (auto s = check_joint_limits(g, start); !s) {
    return s.error().with_context("start");
  }
  if (auto s = check_singularity(g, start, limits.singularity_margin); !s) {
    return s.error().with_context("start");
  }
  CartesianPath path;
  path.geometry_ = g;
  path.elbow_ = elbow_of(start);
  path.start_ = start;
  path.cycle_ = limits.cycle;
  ScaraJoints joints = start;
  path.segments_.reserve(waypoints.size());
  SF_TRY(build_lines(g, limits, path.elbow_, joints, waypoints, path.segments_));
  path.end_ = joints;
  auto& lines = path.segments_;
  for (std::size_t k = 0; k + 1 < lines.size(); ++k) {
    lines[k + 1].start = next_start(g, limits, path.elbow_, lines, k);
  }
  path.arrivals_.assign(waypoints.size(), 0.0);
  double end = 0.0;
  for (const auto& s : lines) {
    path.arrivals_[s.waypoint] = s.end();
    end = s.end() + s.dwell;
  }
  for (std::size_t i = 1; i < waypoints.size(); ++i) {
    path.arrivals_[i] = std::max(path.arrivals_[i], path.arrivals_[i - 1]);
  }
  path.cycles_ = detail::whole_cycles(end, limits.cycle);
  return path;
}

Result<CartesianPath> plan_line(const ScaraGeometry& g, const MotionLimits& limits, const ScaraJoints& start,
                                const ToolPose& target) {
  const Waypoint w{target, 0.0, 0.0};
  return plan_path(g, limits, start, std::span<const Waypoint>(&w, 1));
}

}  // namespace sf::motion
