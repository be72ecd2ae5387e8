#include "sf/motion/scara.hpp"

#include <cmath>
#include <numbers>

#include <gtest/gtest.h>

namespace sf::motion {
namespace {

constexpr double kPi = std::numbers::pi;

ScaraGeometry arm() {
  ScaraGeometry g;
  g.base = {1.0, 2.0, 0.5};
  g.l1 = 0.3;
  g.l2 = 0.2;
  return g;
}

TEST(ScaraTest, ForwardOfClosedFormPoses) {
  const auto g = arm();
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
  const auto g = arm();
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
  auto g = arm();
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
  auto g = arm();
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
  const auto g = arm();
  const ToolPose target{{1.3, 2.2, 0.6}, 0.0};
  auto from_left = scara_inverse_nearest(g, target, {0.0, 1.0, 0.1, 0.0});
  auto from_right = scara_inverse_nearest(g, target, {1.0, -1.0, 0.1, 0.0});
  ASSERT_TRUE(from_left && from_right);
  EXPECT_GT((*from_left)[1], 0.0);
  EXPECT_LT((*from_right)[1], 0.0);
}

}  // namespace
}  // namespace sf::motion
