#include "sf/motion/articulated.hpp"

#include <cmath>
#include <numbers>

#include <gtest/gtest.h>

namespace sf::motion {
namespace {

ArticulatedGeometry articulated_arm() {
  ArticulatedGeometry g;
  g.base = {0.5, -0.5, 0.0};
  return g;
}

TEST(ArticulatedTest, ForwardOfAStretchedArmPointingDown) {
  const auto g = articulated_arm();
  // Upper arm and forearm horizontal along the base's +x, tool straight down.
  const auto p = articulated_forward(g, {0.0, 0.0, 0.0, 0.0, -std::numbers::pi / 2, 0.0});
  EXPECT_NEAR(p.position.x, 0.5 + 0.6, 1e-12);
  EXPECT_NEAR(p.position.y, -0.5, 1e-12);
  EXPECT_NEAR(p.position.z, 0.28 - 0.08, 1e-12);
}

TEST(ArticulatedTest, InverseComesBackWithTheToolDown) {
  const auto g = articulated_arm();
  const ToolPose target{{0.9, -0.2, 0.15}, 0.3};
  auto q = articulated_inverse(g, target);
  ASSERT_TRUE(q) << q.error().describe();
  const auto p = articulated_forward(g, *q);
  EXPECT_NEAR(p.position.x, target.position.x, 1e-9);
  EXPECT_NEAR(p.position.y, target.position.y, 1e-9);
  EXPECT_NEAR(p.position.z, target.position.z, 1e-9);
  EXPECT_NEAR(wrap_angle(p.yaw - target.yaw), 0.0, 1e-9);
  EXPECT_NEAR((*q)[1] + (*q)[2] + (*q)[4], -std::numbers::pi / 2, 1e-12);  // tool vertical
  EXPECT_LT((*q)[2], 0.0);                                                 // elbow up
}

TEST(ArticulatedTest, UnreachableAndSingularPointsAreErrors) {
  const auto g = articulated_arm();
  EXPECT_FALSE(articulated_inverse(g, {{2.0, -0.5, 0.2}, 0.0}));
  EXPECT_FALSE(articulated_inverse(g, {{0.5, -0.5, 0.2}, 0.0}));  // on the base axis
  EXPECT_TRUE(articulated_reaches(g, {0.9, -0.5, 0.1}));
  EXPECT_FALSE(articulated_reaches(g, {0.9, -0.5, 1.5}));
}

}  // namespace
}  // namespace sf::motion
