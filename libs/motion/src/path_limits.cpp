#include "path_limits.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <span>

#include <fmt/format.h>

namespace sf::motion::detail {

namespace {

// Samples of q', q'', q''' along a line, besides its closest approach to the
// shoulder axis: one every kSampleSpacing of horizontal travel, at most
// kLineSamples. They depend on the horizontal position only (z is its own
// axis, yaw only adds to θ4), so a vertical line needs its two ends alone.
// Close enough that the peaks between them stay within the share of each
// limit kept back for them (the random-path test checks it).
constexpr double kSampleSpacing = 0.025;  // m
constexpr int kLineSamples = 24;
// Samples over a blend's overlap (tens of milliseconds).
constexpr int kOverlapSamples = 8;
// The share of each axis limit a sampled check may use: the rest covers the
// peaks between samples.
constexpr double kSampledShare = 0.95;

// q', q'', q''' at a point u of a line.
struct Sample {
  double u = 0.0;
  JointDerivatives d;
};

// The samples along a line: the grid and its closest approach.
struct Samples {
  std::array<Sample, kLineSamples + 2> at{};
  std::size_t size = 0;
  [[nodiscard]] std::span<const Sample> all() const { return {at.data(), size}; }
};

// Where the line's horizontal projection comes closest to the shoulder axis:
// there |θ2| and, near the inner radius, the joint rates peak.
double closest_approach(const ScaraGeometry& g, const PathSegment& line) {
  const Vec2 d = line.delta.xy();
  const double dd = dot(d, d);
  return dd == 0.0 ? 0.0 : std::clamp(-dot(line.from.position.xy() - g.base.xy(), d) / dd, 0.0, 1.0);
}

// The joints at pose, in reach, within limits and out of the singularity margin.
Result<ScaraJoints> solve_checked(const ScaraGeometry& g, const MotionLimits& limits, Elbow elbow,
                                  const ToolPose& pose, const ScaraJoints& near) {
  auto q = scara_inverse_along(g, pose, elbow, near);
  if (!q) {
    return q.error();
  }
  SF_TRY(check_joint_limits(g, *q));
  SF_TRY(check_singularity(g, *q, limits.singularity_margin));
  return q;
}

Status visit(const ScaraGeometry& g, const MotionLimits& limits, Elbow elbow, const PathSegment& line,
             double u, ScaraJoints& joints, Samples& samples) {
  auto q = solve_checked(g, limits, elbow, line.at(u), joints);
  if (!q) {
    return q.error();
  }
  PoseDerivatives p;
  p.first = {line.delta.x, line.delta.y, line.delta.z, line.yaw_delta};  // a line: p'' = p''' = 0
  samples.at[samples.size++] = {u, scara_joint_derivatives(g, *q, p)};
  joints = *q;
  return {};
}

// Lowers u's bounds to what a limit allows when one unit of u moves the
// limited quantity by `per_u`.
void cap(AxisLimit& bound, const AxisLimit& limit, double per_u) {
  if (per_u > 0.0) {
    bound.velocity = std::min(bound.velocity, limit.velocity / per_u);
    bound.acceleration = std::min(bound.acceleration, limit.acceleration / per_u);
    bound.jerk = std::min(bound.jerk, limit.jerk / per_u);
  }
}

AxisLimit share(const AxisLimit& l) {
  return {kSampledShare * l.velocity, kSampledShare * l.acceleration, kSampledShare * l.jerk};
}

// How much to slow u's profile (time ×k: its peaks drop by k, k², k³) so
// that the terms the bounds above ignore (q''·u̇² in acceleration; q'''·u̇³
// and 3·q''·u̇·ü in jerk) fit too. At a sample u the profile is no faster
// than √(2·a·d) with d its distance from either end (v·dv = a·du), which
// keeps near-singular ends, where q'' peaks, from being charged the
// cruise velocity.
double slowdown(const JerkProfile& u, std::span<const Sample> samples, const AxisLimits& axes) {
  const double a = u.peak_acceleration();
  const double j = u.peak_jerk();
  double k = 1.0;
  for (const Sample& s : samples) {
    const double v = std::min(u.peak_velocity(), std::sqrt(2.0 * a * std::min(s.u, 1.0 - s.u)));
    for (std::size_t i = 0; i < axes.size(); ++i) {
      const AxisLimit l = share(axes[i]);
      const double d1 = std::abs(s.d.first[i]);
      const double d2 = std::abs(s.d.second[i]);
      const double d3 = std::abs(s.d.third[i]);
      k = std::max(k, std::sqrt((d2 * v * v + d1 * a) / l.acceleration));
      k = std::max(k, std::cbrt((d3 * v * v * v + 3.0 * d2 * v * a + d1 * j) / l.jerk));
    }
  }
  return k;
}

bool within(double value, double limit) {
  return std::abs(value) <= limit;
}

bool within(const JointDerivatives& d, const AxisLimits& axes) {
  for (std::size_t i = 0; i < axes.size(); ++i) {
    const AxisLimit l = share(axes[i]);
    if (!within(d.first[i], l.velocity) || !within(d.second[i], l.acceleration) ||
        !within(d.third[i], l.jerk)) {
      return false;
    }
  }
  return true;
}

double linear(const std::array<double, 4>& d) {
  return std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
}

bool within(const PoseDerivatives& p, const ToolLimits& tool) {
  return linear(p.first) <= tool.linear.velocity && linear(p.second) <= tool.linear.acceleration &&
         linear(p.third) <= tool.linear.jerk && within(p.first[3], tool.yaw.velocity) &&
         within(p.second[3], tool.yaw.acceleration) && within(p.third[3], tool.yaw.jerk);
}

// Adds `scale`·(the line's delta in x, y, z, yaw) to `d`.
void add(std::array<double, 4>& d, const PathSegment& line, double scale) {
  d[0] += scale * line.delta.x;
  d[1] += scale * line.delta.y;
  d[2] += scale * line.delta.z;
  d[3] += scale * line.yaw_delta;
}

// The line's closest approach to the shoulder axis: how far the arm folds
// (θ2's limit, the inner radius) depends only on it.
Status check_closest_approach(const ScaraGeometry& g, const MotionLimits& limits, Elbow elbow,
                              const PathSegment& line, double u, const ScaraJoints& joints) {
  const ToolPose pose = line.at(u);
  auto q = scara_inverse_along(g, pose, elbow, joints);
  Status s = q ? check_singularity(g, *q, limits.singularity_margin) : Status(q.error());
  if (s && !g.limits[1].contains((*q)[1])) {
    s = make_error(Errc::out_of_range,
                   fmt::format("the elbow would fold past its limits to θ2 = {:.4f} ([{:.4f}, {:.4f}])",
                               (*q)[1], g.limits[1].min, g.limits[1].max));
  }
  if (!s) {
    const double r = norm(pose.position.xy() - g.base.xy());
    return s.error().with_context(fmt::format("passes {:.4f} m from the shoulder axis", r));
  }
  return {};
}

}  // namespace

Result<JerkProfile> line_profile(const ScaraGeometry& g, const MotionLimits& limits, Elbow elbow,
                                 const PathSegment& line, ScaraJoints& joints) {
  Samples samples;
  const double closest = closest_approach(g, line);
  SF_TRY(check_closest_approach(g, limits, elbow, line, closest, joints));
  bool closest_seen = closest <= 0.0 || closest >= 1.0;
  const int n =
      std::clamp(static_cast<int>(std::ceil(norm(line.delta.xy()) / kSampleSpacing)), 1, kLineSamples);
  for (int i = 0; i <= n; ++i) {
    const double u = static_cast<double>(i) / n;
    if (!closest_seen && closest < u) {
      SF_TRY(visit(g, limits, elbow, line, closest, joints, samples));
      closest_seen = true;
    }
    SF_TRY(visit(g, limits, elbow, line, u, joints, samples));
  }
  constexpr double kUnbounded = std::numeric_limits<double>::infinity();
  AxisLimit bound{kUnbounded, kUnbounded, kUnbounded};
  cap(bound, limits.tool.linear, line.length);
  cap(bound, limits.tool.yaw, std::abs(line.yaw_delta));
  for (std::size_t i = 0; i < limits.axes.size(); ++i) {
    double most = 0.0;  // largest |q'|
    for (const Sample& sample : samples.all()) {
      most = std::max(most, std::abs(sample.d.first[i]));
    }
    cap(bound, share(limits.axes[i]), most);
  }
  const JerkProfile fastest = JerkProfile::fastest(1.0, bound);
  return fastest.stretched(fastest.duration() * slowdown(fastest, samples.all(), limits.axes));
}

bool overlap_within_limits(const ScaraGeometry& g, const MotionLimits& limits, Elbow elbow,
                           const PathSegment& a, const PathSegment& b, double b_start,
                           const ScaraJoints& joints) {
  ScaraJoints near = joints;
  for (int i = 0; i <= kOverlapSamples; ++i) {
    const double t = b_start + (a.end() - b_start) * i / kOverlapSamples;
    const ProfileState ua = a.profile.at(t - a.start);
    const ProfileState ub = b.profile.at(t - b_start);
    ToolPose pose = a.at(ua.position);
    pose.position = pose.position + ub.position * b.delta;
    pose.yaw += ub.position * b.yaw_delta;
    PoseDerivatives p;
    add(p.first, a, ua.velocity);
    add(p.first, b, ub.velocity);
    add(p.second, a, ua.acceleration);
    add(p.second, b, ub.acceleration);
    add(p.third, a, ua.jerk);
    add(p.third, b, ub.jerk);
    auto q = solve_checked(g, limits, elbow, pose, near);
    if (!q || !within(p, limits.tool) || !within(scara_joint_derivatives(g, *q, p), limits.axes)) {
      return false;
    }
    near = *q;
  }
  return true;
}

}  // namespace sf::motion::detail
