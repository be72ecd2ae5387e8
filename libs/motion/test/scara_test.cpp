#include "sf/motion/scara.hpp"

#include <cmath>
#include <numbers>

#include <gtest/gtest.h>

#include "sf/motion/scara_differential.hpp"
#include "sf/motion/testing/scara_cell.hpp"

namespace sf::motion {
namespace {

constexpr double kPi = std::numbers::pi;

ScaraGeometry scara_arm() {
  ScaraGeometry g;
  g.base = {1.0, 2.0, 0.5};
  g.l1 = 0.3;
  g.l2 = 0.2;
  return g;
}

TEST(ScaraTest, ForwardOfClosedFormPoses) {
  const auto g = scara_arm();
  // Stretched along x.
  auto p = scara_forward(g, {0.0, 0.0, 0.1, 0.0});
  EXPECT_NEAR(p.position.x, 1.5, 1e-12);
  EXPECT_NEAR(p.position.y, 2.0, 1e-12);
  EXPECT_NEAR(p.position.z, 0.6, 1e-12);
  EXPECT_NEAR(p.yaw, 0.0, 1e-12);
  // Shoulder at 90°, elbow at −90°: upper arm along +y, forearm along +x.
  p = scara_forward(g, {kPi / 2, -kPi / 2, 0.0, 0.25});
  EXPECT_NEAR(p.position.x, 1.2, 1e-12);
  EXPECT_NEAR(p.position.y, 2.3, 1e-12);
  EXPECT_NEAR(p.yaw, 0.25, 1e-12);
}

TEST(ScaraTest, InverseGivesBothElbowsAndEachComesBack) {
  const auto g = scara_arm();
  const ToolPose target{{1.25, 2.3, 0.62}, 0.4};
  auto left = scara_inverse(g, target, Elbow::left);
  auto right = scara_inverse(g, target, Elbow::right);
  ASSERT_TRUE(left) << left.error().describe();
  ASSERT_TRUE(right) << right.error().describe();
  EXPECT_GT((*left)[1], 0.0);
  EXPECT_LT((*right)[1], 0.0);
  for (const auto& q : {*left, *right}) {
    const auto p = scara_forward(g, q);
    EXPECT_NEAR(p.position.x, target.position.x, 1e-9);
    EXPECT_NEAR(p.position.y, target.position.y, 1e-9);
    EXPECT_NEAR(p.position.z, target.position.z, 1e-9);
    EXPECT_NEAR(wrap_angle(p.yaw - target.yaw), 0.0, 1e-9);
  }
  // Law of cosines by hand: r² = 0.25² + 0.3² → cos θ2 = (r² − 0.13) / 0.12.
  const double r2 = 0.25 * 0.25 + 0.3 * 0.3;
  EXPECT_NEAR(std::cos((*left)[1]), (r2 - 0.13) / 0.12, 1e-12);
}

TEST(ScaraTest, OutOfReachAndSingularCentreAreErrors) {
  auto g = scara_arm();
  auto far = scara_inverse(g, {{1.6, 2.0, 0.6}, 0.0}, Elbow::left);
  ASSERT_FALSE(far);
  EXPECT_NE(far.error().message.find("beyond the reach"), std::string::npos);
  auto inner = scara_inverse(g, {{1.05, 2.0, 0.6}, 0.0}, Elbow::left);
  ASSERT_FALSE(inner);
  EXPECT_NE(inner.error().message.find("inside"), std::string::npos);
  g.l2 = g.l1;  // equal links: the centre is reachable in theory but θ1 is undefined there
  auto centre = scara_inverse(g, {{1.0, 2.0, 0.6}, 0.0}, Elbow::left);
  ASSERT_FALSE(centre);
  EXPECT_FALSE(scara_reaches(g, {1.0, 2.0, 0.6}));
}

TEST(ScaraTest, JointLimitsRefuseAConfigurationAndNearestPicksTheOther) {
  auto g = scara_arm();
  g.limits[1] = {-2.5, 0.0};  // the elbow may only bend right
  const ToolPose target{{1.25, 2.3, 0.6}, 0.0};
  auto left = scara_inverse(g, target, Elbow::left);
  ASSERT_FALSE(left);
  EXPECT_NE(left.error().message.find("θ2"), std::string::npos);
  auto nearest = scara_inverse_nearest(g, target, {0.0, 1.0, 0.0, 0.0});
  ASSERT_TRUE(nearest);
  EXPECT_LT((*nearest)[1], 0.0);
  auto z_low = scara_inverse(g, {{1.25, 2.3, 0.4}, 0.0}, Elbow::right);  // below the z stroke
  ASSERT_FALSE(z_low);
}

TEST(ScaraTest, NearestKeepsTheCurrentElbow) {
  const auto g = scara_arm();
  const ToolPose target{{1.3, 2.2, 0.6}, 0.0};
  auto from_left = scara_inverse_nearest(g, target, {0.0, 1.0, 0.1, 0.0});
  auto from_right = scara_inverse_nearest(g, target, {1.0, -1.0, 0.1, 0.0});
  ASSERT_TRUE(from_left && from_right);
  EXPECT_GT((*from_left)[1], 0.0);
  EXPECT_LT((*from_right)[1], 0.0);
}

// FK∘IK: every joint vector within limits, away from θ2 = 0 and ±π where
// the two elbows coincide, comes back from the pose it puts the tool at, in
// its own elbow and on its own turn.
TEST(ScaraTest, InverseOfForwardOverTheWorkspaceGridBothElbows) {
  const auto g = testing::robot1();
  int solved = 0;
  for (int a = 0; a <= 26; ++a) {
    const double q1 = -2.6 + 0.2 * a;
    for (int b = 0; b <= 49; ++b) {
      const double q2 = -2.45 + 0.1 * b;
      if (std::abs(std::sin(q2)) < 1e-3) {
        continue;
      }
      for (double z : {0.0, 0.12, 0.3}) {
        for (double q4 : {-3.0, -0.5, 1.2, 3.1}) {
          const ScaraJoints q{q1, q2, z, q4};
          const ToolPose p = scara_forward(g, q);
          auto back = scara_inverse(g, p, elbow_of(q), q);
          ASSERT_TRUE(back) << back.error().describe();
          for (std::size_t i = 0; i < 4; ++i) {
            EXPECT_NEAR((*back)[i], q[i], 1e-9) << "joint " << i << " of " << q1 << " " << q2;
          }
          ++solved;
        }
      }
    }
  }
  EXPECT_GT(solved, 5000);
}

// IK∘FK: every pose on a grid of the workspace (annulus × z stroke × yaw)
// that an elbow reaches within limits is reached exactly by it.
TEST(ScaraTest, ForwardOfInverseOverTheWorkspaceGridBothElbows) {
  const auto g = testing::robot1();
  int reached[2] = {0, 0};
  for (int i = 0; i <= 24; ++i) {
    const double r = 0.06 + 0.02 * i;  // 0.06 … 0.54 m
    for (int j = 0; j < 42; ++j) {
      const double phi = -kPi + 0.15 * j;
      for (double z : {0.8, 0.95, 1.1}) {
        for (double yaw : {-2.0, 0.0, 2.9}) {
          const ToolPose target{{g.base.x + r * std::cos(phi), g.base.y + r * std::sin(phi), z}, yaw};
          for (const Elbow e : {Elbow::left, Elbow::right}) {
            auto q = scara_inverse(g, target, e);
            if (!q) {
              continue;
            }
            ++reached[e == Elbow::left ? 0 : 1];
            EXPECT_EQ(elbow_of(*q), e);
            const ToolPose p = scara_forward(g, *q);
            EXPECT_NEAR(norm(p.position - target.position), 0.0, 1e-9);
            EXPECT_NEAR(wrap_angle(p.yaw - target.yaw), 0.0, 1e-9);
          }
        }
      }
    }
  }
  // θ2 within ±2.5 rad keeps the tool 0.18 m or more from the shoulder, θ1
  // within ±2.6 rad leaves a sector out: most of the grid, not all of it.
  EXPECT_GT(reached[0], 1500);
  EXPECT_GT(reached[1], 1500);
}

TEST(ScaraTest, NearPicksTheWristTurnWithinLimits) {
  auto g = scara_arm();
  const ScaraJoints now{0.3, 1.0, 0.1, 3.1};
  // A yaw whose wrapped θ4 is −3.1: the nearest turn, 3.18, is past +π.
  const ToolPose target{scara_forward(g, {0.3, 1.0, 0.1, -3.1}).position,
                        scara_forward(g, {0.3, 1.0, 0.1, -3.1}).yaw};
  auto inside = scara_inverse(g, target, Elbow::left, now);
  ASSERT_TRUE(inside) << inside.error().describe();
  EXPECT_NEAR((*inside)[3], -3.1, 1e-9);
  g.limits[3] = {-2.0 * kPi, 2.0 * kPi};  // a wrist with two turns of range
  auto near = scara_inverse(g, target, Elbow::left, now);
  ASSERT_TRUE(near);
  EXPECT_NEAR((*near)[3], -3.1 + 2.0 * kPi, 1e-9);
}

TEST(ScaraTest, AlongFollowsTheWristAcrossPiWithoutATurn) {
  const auto g = scara_arm();
  ScaraJoints previous{0.3, 1.0, 0.1, 3.0};
  const Vec3 at = scara_forward(g, previous).position;
  for (int step = 0; step < 50; ++step) {
    const double wanted = scara_forward(g, previous).yaw + 0.01;
    auto q = scara_inverse_along(g, {at, wanted}, Elbow::left, previous);
    ASSERT_TRUE(q);
    EXPECT_NEAR((*q)[3] - previous[3], 0.01, 1e-9);
    previous = *q;
  }
  EXPECT_GT(previous[3], kPi);  // past the wrap, continuous
}

TEST(ScaraTest, SingularityCheckNamesFullStretchAndTheInnerRadius) {
  const auto g = scara_arm();
  EXPECT_TRUE(check_singularity(g, {0.0, 0.5, 0.0, 0.0}, 0.1));
  auto stretched = check_singularity(g, {0.0, 0.02, 0.0, 0.0}, 0.1);
  ASSERT_FALSE(stretched);
  EXPECT_NE(stretched.error().message.find("full stretch"), std::string::npos) << stretched.error().message;
  auto folded = check_singularity(g, {0.0, -3.1, 0.0, 0.0}, 0.1);
  ASSERT_FALSE(folded);
  EXPECT_NE(folded.error().message.find("inner radius"), std::string::npos) << folded.error().message;
  EXPECT_NEAR(scara_conditioning({0.0, kPi / 2, 0.0, 0.0}), 1.0, 1e-12);
}

// The closed-form joint derivatives against finite differences of the
// inverse along a curved tool motion.
TEST(ScaraTest, JointDerivativesMatchFiniteDifferencesOfTheInverse) {
  const auto g = scara_arm();
  const auto pose = [](double s) {
    return ToolPose{{1.25 + 0.05 * s + 0.02 * s * s, 2.25 - 0.03 * s * s * s, 0.6 + 0.01 * s}, 0.2 + 0.3 * s};
  };
  const double s = 0.4;
  const double h = 1e-3;
  std::array<ScaraJoints, 5> q{};
  for (std::size_t i = 0; i < q.size(); ++i) {
    q[i] = scara_inverse(g, pose(s + (static_cast<double>(i) - 2.0) * h), Elbow::left).value();
  }
  PoseDerivatives p;
  p.first = {0.05 + 0.04 * s, -0.09 * s * s, 0.01, 0.3};
  p.second = {0.04, -0.18 * s, 0.0, 0.0};
  p.third = {0.0, -0.18, 0.0, 0.0};
  const auto d = scara_joint_derivatives(g, q[2], p);
  for (std::size_t j = 0; j < 4; ++j) {
    const double d1 = (q[3][j] - q[1][j]) / (2 * h);
    const double d2 = (q[3][j] - 2 * q[2][j] + q[1][j]) / (h * h);
    const double d3 = (q[4][j] - 2 * q[3][j] + 2 * q[1][j] - q[0][j]) / (2 * h * h * h);
    EXPECT_NEAR(d.first[j], d1, 1e-5) << "joint " << j;
    EXPECT_NEAR(d.second[j], d2, 1e-4) << "joint " << j;
    EXPECT_NEAR(d.third[j], d3, 1e-2 * std::max(1.0, std::abs(d3))) << "joint " << j;
  }
}

}  // namespace
}  // namespace sf::motion
