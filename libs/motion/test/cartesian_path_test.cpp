#include "sf/motion/cartesian_path.hpp"

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "sf/motion/csp_sampler.hpp"
#include "sf/motion/testing/scara_cell.hpp"

namespace sf::motion {
namespace {

using testing::above;
using testing::robot1;

// The cycle times from `from` to `until`, both included.
std::vector<double> cycles_between(double from, double until, double cycle) {
  std::vector<double> t;
  const auto n = static_cast<int>(std::floor((until - from) / cycle + 1e-9));
  for (int k = 0; k <= n; ++k) {
    t.push_back(from + k * cycle);
  }
  return t;
}

// The tool point the set-points put the arm at, and between set-points
// where a drive moves each axis on a straight line from one target to the
// next: `between` points per cycle.
std::vector<Vec3> tool_points(const ScaraGeometry& g, const std::vector<ScaraJoints>& q, int between) {
  std::vector<Vec3> points;
  for (std::size_t k = 1; k < q.size(); ++k) {
    for (int i = 0; i < between; ++i) {
      const double s = static_cast<double>(i) / between;
      ScaraJoints mid{};
      for (std::size_t j = 0; j < 4; ++j) {
        mid[j] = q[k - 1][j] + s * (q[k][j] - q[k - 1][j]);
      }
      points.push_back(scara_forward(g, mid).position);
    }
  }
  points.push_back(scara_forward(g, q.back()).position);
  return points;
}

TEST(CartesianPathTest, ALineStaysWithinATenthOfAMillimetreOfTheLine) {
  const auto g = robot1();
  const MotionLimits lim;
  const ScaraJoints start = scara_inverse(g, {above(testing::kGummy, 0.05), 0.0}, Elbow::left).value();
  const ToolPose target{testing::kHome, 0.7};
  auto line = plan_line(g, lim, start, target);
  ASSERT_TRUE(line) << line.error().describe();
  const auto q = testing::setpoints(CspSampler(*line), start);
  ASSERT_EQ(q.size(), line->cycles() + 1);
  const Vec3 a = above(testing::kGummy, 0.05);
  double worst = 0.0;
  for (const Vec3& p : tool_points(g, q, 10)) {
    worst = std::max(worst, testing::distance_to_segment(p, a, target.position));
  }
  EXPECT_LT(worst, 1e-4);
  // The set-points themselves are on the line to rounding.
  for (const auto& joints : q) {
    EXPECT_LT(testing::distance_to_segment(scara_forward(g, joints).position, a, target.position), 1e-9);
  }
  // And the continuous path between cycles.
  for (int i = 0; i <= 997; ++i) {
    const double t = line->duration() * i / 997;
    EXPECT_LT(testing::distance_to_segment(line->pose_at(t).position, a, target.position), 1e-12);
  }
  EXPECT_NEAR(norm(scara_forward(g, q.back()).position - target.position), 0.0, 1e-12);
  EXPECT_NEAR(wrap_angle(scara_forward(g, q.back()).yaw - 0.7), 0.0, 1e-12);
}

TEST(CartesianPathTest, ALineStepsWithinTheAxisLimitsAndTheToolSpeed) {
  const auto g = robot1();
  const MotionLimits lim;
  const ScaraJoints start = testing::home(g);
  for (const ToolPose& target :
       {ToolPose{testing::kGummy, 0.0}, ToolPose{testing::kSlot8, 1.5}, ToolPose{{3.95, 0.5, 1.1}, -2.0}}) {
    auto line = plan_line(g, lim, start, target);
    ASSERT_TRUE(line) << line.error().describe();
    const auto q = testing::setpoints(CspSampler(*line), start);
    const auto peaks = testing::step_peaks(q, lim.cycle, lim.axes);
    EXPECT_LE(peaks.worst(), 1.0) << "to " << target.position.x << " " << target.position.y;
    for (std::size_t k = 1; k < q.size(); ++k) {
      const double step = norm(scara_forward(g, q[k]).position - scara_forward(g, q[k - 1]).position);
      EXPECT_LE(step, lim.tool.linear.velocity * lim.cycle * (1 + 1e-9));
    }
  }
}

// Along the outer edge of the reach (|sin θ2| ≈ 0.2) a line needs joint
// rates five times those of the middle of the workspace for the same tool
// speed: the planner slows it down, and the steps stay within the limits.
TEST(CartesianPathTest, ALineNearFullStretchIsSlowedDownWithinTheLimits) {
  const auto g = robot1();
  MotionLimits lim;
  const double r_edge = std::sqrt(0.3 * 0.3 + 0.25 * 0.25 + 2 * 0.3 * 0.25 * std::cos(0.2));
  const auto on_circle = [&](double r, double phi) {
    return ToolPose{{g.base.x + r * std::cos(phi), g.base.y + r * std::sin(phi), 0.9}, 0.0};
  };
  // Two radial lines of the same length, 20 mm: one out to the edge, one
  // mid-reach (along the edge the arm just turns θ1: no singularity there).
  const ScaraJoints edge_start = scara_inverse(g, on_circle(r_edge - 0.02, 0.5), Elbow::left).value();
  auto edge = plan_line(g, lim, edge_start, on_circle(r_edge, 0.5));
  ASSERT_TRUE(edge) << edge.error().describe();
  const ScaraJoints mid_start = scara_inverse(g, on_circle(0.37, 0.5), Elbow::left).value();
  auto mid = plan_line(g, lim, mid_start, on_circle(0.39, 0.5));
  ASSERT_TRUE(mid);
  EXPECT_GT(edge->duration(), 1.5 * mid->duration());
  const auto peaks =
      testing::step_peaks(testing::setpoints(CspSampler(*edge), edge_start), lim.cycle, lim.axes);
  EXPECT_LE(peaks.worst(), 1.0);
  // A joint limit, not the tool's, set the pace: some axis is close to it.
  EXPECT_GT(std::max({peaks.velocity[0], peaks.velocity[1], peaks.acceleration[0], peaks.acceleration[1]}),
            0.5);
}

TEST(CartesianPathTest, SingularAndUnreachableTargetsAreRefusedNamingTheCause) {
  auto g = robot1();
  const MotionLimits lim;
  const ScaraJoints start = testing::home(g);
  const auto expect_refused = [&](const ScaraGeometry& geometry, const ToolPose& target, const char* cause) {
    auto line = plan_line(geometry, lim, start, target);
    ASSERT_FALSE(line) << "to " << target.position.x << " " << target.position.y;
    EXPECT_NE(line.error().message.find(cause), std::string::npos) << line.error().message;
  };
  expect_refused(g, {{4.2, 0.35, 0.9}, 0.0}, "beyond the reach");
  expect_refused(g, {{3.5 + 0.5495, 0.35, 0.9}, 0.0}, "full stretch");  // |sin θ2| ≈ 0.08
  expect_refused(g, {{3.9, 0.35, 0.7}, 0.0}, "joint z");
  // Straight from a dispenser to a slot: 0.13 m from the shoulder axis.
  const ScaraJoints at_gummy = scara_inverse(g, {testing::kGummy, 0.0}, Elbow::left).value();
  auto direct = plan_line(g, lim, at_gummy, {testing::kSlot3, 0.0});
  ASSERT_FALSE(direct);
  EXPECT_NE(direct.error().message.find("passes 0.12"), std::string::npos) << direct.error().message;
  EXPECT_NE(direct.error().message.find("fold past its limits"), std::string::npos) << direct.error().message;
  // Across the shoulder, 0.02 m from its axis: inside |l1 − l2|, and, with
  // an elbow that folds further, 0.055 m from it: reachable but singular.
  g.limits[1] = {-3.1, 3.1};
  const ScaraJoints west = scara_inverse(g, {{3.2, 0.37, 0.9}, 0.0}, Elbow::left).value();
  auto unreachable = plan_line(g, lim, west, {{3.8, 0.37, 0.9}, 0.0});
  ASSERT_FALSE(unreachable);
  EXPECT_NE(unreachable.error().message.find("inner radius 0.0500 m the arm cannot reach"), std::string::npos)
      << unreachable.error().message;
  EXPECT_NE(unreachable.error().message.find("way-point 0"), std::string::npos)
      << unreachable.error().message;
  const ScaraJoints north = scara_inverse(g, {{3.2, 0.405, 0.9}, 0.0}, Elbow::left).value();
  auto folded = plan_line(g, lim, north, {{3.8, 0.405, 0.9}, 0.0});
  ASSERT_FALSE(folded);
  EXPECT_NE(folded.error().message.find("nearly folded, the singular inner radius"), std::string::npos)
      << folded.error().message;
}

// At φ = −2.5 rad the left elbow needs θ1 below −2.6; the right one reaches.
TEST(CartesianPathTest, AWaypointNeedingTheOtherElbowIsRefused) {
  const auto g = robot1();
  const ScaraJoints start = testing::home(g);
  ASSERT_EQ(elbow_of(start), Elbow::left);
  const ToolPose behind{{3.5 + 0.4 * std::cos(-2.5), 0.35 + 0.4 * std::sin(-2.5), 0.9}, 0.0};
  ASSERT_TRUE(scara_inverse(g, behind, Elbow::right));
  auto line = plan_line(g, MotionLimits{}, start, behind);
  ASSERT_FALSE(line);
  EXPECT_NE(line.error().message.find("right elbow"), std::string::npos) << line.error().message;
}

TEST(CartesianPathTest, TheElbowNeverFlipsAndTheWristTurnsTheShortWay) {
  const auto g = robot1();
  const MotionLimits lim;
  ScaraJoints start = scara_inverse(g, {testing::kChocolate, 3.0}, Elbow::left).value();
  // Yaw 3.0 → −3.0: 0.28 rad the short way across ±π.
  const std::vector<Waypoint> points{{{testing::kGummy, -3.0}, 0.0, 0.0},
                                     {{testing::kHome, 2.0}, 0.0, 0.0},
                                     {{testing::kSlot3, 2.0}, 0.0, 0.0}};
  auto path = plan_path(g, lim, start, points);
  ASSERT_TRUE(path) << path.error().describe();
  const auto q = testing::setpoints(CspSampler(*path), start);
  for (const auto& joints : q) {
    EXPECT_GT(joints[1], 0.0);
  }
  EXPECT_LE(testing::step_peaks(q, lim.cycle, lim.axes).worst(), 1.0);
  EXPECT_LT(std::abs(path->segments()[0].yaw_delta), 0.3);
}

using testing::pick_and_place;

TEST(CartesianPathTest, BlendedCornersStayWithinTheRadiusWithoutStopping) {
  const auto g = robot1();
  const MotionLimits lim;
  const ScaraJoints start = testing::home(g);
  const double radius = 0.02;
  const auto points = pick_and_place(radius);
  auto blended = plan_path(g, lim, start, points);
  ASSERT_TRUE(blended) << blended.error().describe();
  auto stopping = plan_path(g, lim, start, pick_and_place(0.0));
  ASSERT_TRUE(stopping);
  EXPECT_LT(blended->duration(), stopping->duration());

  std::vector<Vec3> corners{scara_forward(g, start).position};
  for (const auto& w : points) {
    corners.push_back(w.pose.position);
  }
  const auto q = testing::setpoints(CspSampler(*blended), start);
  double worst = 0.0;
  for (const Vec3& p : tool_points(g, q, 4)) {
    worst = std::max(worst, testing::distance_to_polyline(p, corners));
  }
  EXPECT_LE(worst, radius);
  EXPECT_GT(worst, 0.1 * radius);  // the corners are cut, not stopped at
  EXPECT_LE(testing::step_peaks(q, lim.cycle, lim.axes).worst(), 1.0);

  // Through the blended way-points (0, 2, 3, 4) the tool keeps moving: its
  // speed does not drop to zero between arriving on one line and leaving on
  // the next. It stops at the pick (1) and the place (5) for their dwell.
  for (std::size_t w : {0U, 2U, 3U, 4U}) {
    const PathSegment& into = blended->segments()[w];
    const PathSegment& out = blended->segments()[w + 1];
    EXPECT_LT(out.start, into.end()) << "way-point " << w;
    for (double t : cycles_between(out.start, into.end(), lim.cycle)) {
      const auto d = blended->derivatives_at(t);
      EXPECT_GT(std::hypot(d.first[0], d.first[1], d.first[2]), 1e-3) << "way-point " << w << " at " << t;
    }
  }
  for (std::size_t w : {1U, 5U}) {
    const double at = blended->arrival(w);
    EXPECT_LT(norm(blended->pose_at(at).position - points[w].pose.position), 1e-12);
    EXPECT_LT(norm(blended->pose_at(at + 0.05).position - points[w].pose.position), 1e-12);
    EXPECT_GE(blended->segments()[w + 1].start, at + 0.05 - 1e-12);
  }
  EXPECT_NEAR(norm(scara_forward(g, q.back()).position - points.back().pose.position), 0.0, 1e-12);
}

// A blend radius larger than half a segment is capped there: the tool still
// passes within half the shorter segment of the corner.
TEST(CartesianPathTest, ABlendRadiusIsCappedAtHalfTheShorterSegment) {
  const auto g = robot1();
  const MotionLimits lim;
  const ScaraJoints start = scara_inverse(g, {testing::kChocolate, 0.0}, Elbow::left).value();
  const std::vector<Waypoint> points{{{above(testing::kChocolate, 0.04), 0.0}, 0.5, 0.0},
                                     {{above(testing::kGummy, 0.04), 0.0}, 0.0, 0.0}};
  auto path = plan_path(g, lim, start, points);
  ASSERT_TRUE(path) << path.error().describe();
  const std::vector<Vec3> corners{testing::kChocolate, points[0].pose.position, points[1].pose.position};
  double worst = 0.0;
  for (double t : cycles_between(0.0, path->duration(), lim.cycle)) {
    worst = std::max(worst, testing::distance_to_polyline(path->pose_at(t).position, corners));
  }
  EXPECT_LE(worst, 0.02);
  EXPECT_GT(worst, 0.001);
}

TEST(CartesianPathTest, BadInputIsRefused) {
  const auto g = robot1();
  const ScaraJoints start = testing::home(g);
  EXPECT_FALSE(plan_line(g, MotionLimits{}, start, {{std::nan(""), 0.3, 0.9}, 0.0}));
  const std::vector<Waypoint> negative{{{testing::kGummy, 0.0}, -0.01, 0.0}};
  EXPECT_FALSE(plan_path(g, MotionLimits{}, start, negative));
  MotionLimits lim;
  lim.tool.linear.velocity = -1.0;
  auto bad = plan_line(g, lim, start, {testing::kGummy, 0.0});
  ASSERT_FALSE(bad);
  EXPECT_NE(bad.error().message.find("tool"), std::string::npos);
  lim = MotionLimits{};
  lim.singularity_margin = 1.0;
  EXPECT_FALSE(plan_line(g, lim, start, {testing::kGummy, 0.0}));
  auto outside = plan_line(g, MotionLimits{}, {2.9, 0.5, 0.1, 0.0}, {testing::kGummy, 0.0});
  ASSERT_FALSE(outside);
  EXPECT_NE(outside.error().message.find("start"), std::string::npos);
}

TEST(CartesianPathTest, NoWaypointsOrOnlyTheStartIsAnEmptyPath) {
  const auto g = robot1();
  const ScaraJoints start = testing::home(g);
  auto none = plan_path(g, MotionLimits{}, start, {});
  ASSERT_TRUE(none);
  EXPECT_EQ(none->cycles(), 0U);
  auto same = plan_line(g, MotionLimits{}, start, scara_forward(g, start));
  ASSERT_TRUE(same);
  EXPECT_EQ(same->cycles(), 0U);
  EXPECT_EQ(same->end_joints(), start);
}

}  // namespace
}  // namespace sf::motion

namespace sf::motion {
namespace {

// Paths through random way-points of the cell's workspace (fixed seed): the
// ones the planner accepts keep every set-point step within the axis limits,
// the tool within 0.1 mm of its lines where it is not blending and within
// the blend radius of the polyline where it is; the refused ones say why.
TEST(CartesianPathTest, RandomPathsInTheCellStayWithinTheLimitsAndOnTheirLines) {
  const auto g = testing::robot1();
  const MotionLimits lim;
  std::mt19937 random(20261127);
  std::uniform_real_distribution<double> radius(0.2, 0.54);
  std::uniform_real_distribution<double> angle(-1.6, 1.6);
  std::uniform_real_distribution<double> height(0.82, 1.08);
  std::uniform_real_distribution<double> yaw(-1.5, 1.5);
  std::uniform_real_distribution<double> blend(0.0, 0.03);
  int planned = 0;
  for (int trial = 0; trial < 60; ++trial) {
    std::vector<Waypoint> points;
    std::vector<Vec3> corners{testing::kHome};
    for (int i = 0; i < 4; ++i) {
      const double r = radius(random);
      const double phi = angle(random);
      points.push_back(
          {{{g.base.x + r * std::cos(phi), g.base.y + r * std::sin(phi), height(random)}, yaw(random)},
           i % 2 == 0 ? blend(random) : 0.0,
           0.0});
      corners.push_back(points.back().pose.position);
    }
    const ScaraJoints start = testing::home(g);
    auto path = plan_path(g, lim, start, points);
    if (!path) {
      EXPECT_FALSE(path.error().message.empty());
      continue;
    }
    ++planned;
    const auto q = testing::setpoints(CspSampler(*path), start);
    const auto peaks = testing::step_peaks(q, lim.cycle, lim.axes);
    EXPECT_LE(std::max({peaks.velocity[0], peaks.velocity[1], peaks.velocity[2], peaks.velocity[3],
                        peaks.acceleration[0], peaks.acceleration[1], peaks.acceleration[2],
                        peaks.acceleration[3]}),
              1.0)
        << "trial " << trial;
    double worst = 0.0;
    for (const auto& joints : q) {
      worst = std::max(worst, testing::distance_to_polyline(scara_forward(g, joints).position, corners));
    }
    EXPECT_LE(worst, 0.03 + 1e-9) << "trial " << trial;
    const auto segments = path->segments();
    for (std::size_t k = 0; k < segments.size(); ++k) {  // outside the overlaps: on the line
      const PathSegment& s = segments[k];
      const double from = k == 0 ? s.start : std::max(s.start, segments[k - 1].end());
      const double until = k + 1 == segments.size() ? s.end() : std::min(s.end(), segments[k + 1].start);
      for (double t : cycles_between(from, until, lim.cycle)) {
        const Vec3 p = path->pose_at(t).position;
        EXPECT_LT(testing::distance_to_segment(p, s.from.position, s.from.position + s.delta), 1e-4);
      }
    }
  }
  EXPECT_GT(planned, 15);
}

}  // namespace
}  // namespace sf::motion
