#include "sf/motion/joint_move.hpp"

#include <cmath>

#include <gtest/gtest.h>

#include "sf/motion/csp_sampler.hpp"
#include "sf/motion/testing/scara_cell.hpp"

namespace sf::motion {
namespace {

using testing::robot1;

MotionLimits limits() {
  return MotionLimits{};
}

// Every axis that moves leaves its start on cycle 1 and reaches its target
// on the last cycle, not before.
TEST(JointMoveTest, AllAxesStartAndEndOnTheSameCycle) {
  const auto g = robot1();
  const ScaraJoints from{-1.0, 1.2, 0.05, 0.0};
  const ScaraJoints to{0.8, 0.4, 0.25, -2.0};
  auto move = plan_joint_move(g, limits(), from, to);
  ASSERT_TRUE(move) << move.error().describe();
  const auto q = testing::setpoints(CspSampler(*move), from);
  ASSERT_EQ(q.size(), move->cycles() + 1);
  for (std::size_t i = 0; i < 4; ++i) {
    EXPECT_NE(q[1][i], from[i]) << "axis " << i << " did not start on cycle 1";
    EXPECT_GT(std::abs(q[q.size() - 2][i] - to[i]), 1e-12) << "axis " << i << " arrived early";
    EXPECT_GT(std::abs(move->at(move->duration() - move->cycle()).velocity[i]), 1e-9) << "axis " << i;
    EXPECT_EQ(q.back()[i], to[i]);
    EXPECT_NEAR(move->at(move->duration()).velocity[i], 0.0, 1e-12);
  }
}

// θ1 moves furthest for its limits: its own fastest profile is the
// duration (on whole cycles); the others are stretched to it.
TEST(JointMoveTest, TheSlowestAxisSetsTheDuration) {
  const auto g = robot1();
  const ScaraJoints from{-2.0, 0.5, 0.1, 0.0};
  const ScaraJoints to{2.0, 0.6, 0.12, 0.1};
  auto move = plan_joint_move(g, limits(), from, to);
  ASSERT_TRUE(move);
  EXPECT_EQ(move->leading_axis(), 0U);
  const double own = JerkProfile::fastest(4.0, limits().axes[0]).duration();
  EXPECT_NEAR(move->duration(), std::ceil(own / 1e-3 - 1e-9) * 1e-3, 1e-12);
  for (std::size_t i = 0; i < 4; ++i) {
    EXPECT_NEAR(move->axis(i).duration(), move->duration(), 1e-12);
  }
  // θ2's 0.1 rad at θ1's pace: time-scaled, far below its limits.
  EXPECT_LT(move->axis(1).peak_velocity(), 0.1 * limits().axes[1].velocity);
}

TEST(JointMoveTest, NoSetPointStepExceedsTheAxisLimits) {
  const auto g = robot1();
  const auto lim = limits();
  for (const auto& [from, to] :
       {std::pair<ScaraJoints, ScaraJoints>{{-2.5, 2.4, 0.0, -3.0}, {2.5, -2.4, 0.3, 3.0}},
        {{0.1, 0.1, 0.1, 0.1}, {0.1001, 0.1, 0.1, 0.1}},
        {{0.0, 1.0, 0.2, 0.0}, {0.3, 0.8, 0.0, 1.5}}}) {
    auto move = plan_joint_move(g, lim, from, to);
    ASSERT_TRUE(move);
    const auto peaks = testing::step_peaks(testing::setpoints(CspSampler(*move), from), lim.cycle, lim.axes);
    EXPECT_LE(peaks.worst(), 1.0 + 1e-9);
  }
  // A long move uses the limits: some axis gets near its velocity limit.
  auto long_move =
      plan_joint_move(g, lim, ScaraJoints{-2.5, 2.4, 0.0, -3.0}, ScaraJoints{2.5, -2.4, 0.3, 3.0});
  const auto peaks = testing::step_peaks(testing::setpoints(CspSampler(*long_move), {-2.5, 2.4, 0.0, -3.0}),
                                         lim.cycle, lim.axes);
  EXPECT_GT(peaks.velocity[0], 0.95);
}

TEST(JointMoveTest, ToAPoseTakesTheNearestConfigurationAndTurn) {
  const auto g = robot1();
  const ScaraJoints from = testing::home(g);
  auto move = plan_joint_move_to(g, limits(), from, ToolPose{testing::kGummy, 0.0});
  ASSERT_TRUE(move) << move.error().describe();
  EXPECT_EQ(elbow_of(move->to()), elbow_of(from));
  EXPECT_NEAR(norm(scara_forward(g, move->to()).position - testing::kGummy), 0.0, 1e-9);
  auto right = plan_joint_move_to(g, limits(), from, ToolPose{testing::kGummy, 0.0}, Elbow::right);
  ASSERT_TRUE(right);
  EXPECT_EQ(elbow_of(right->to()), Elbow::right);
}

TEST(JointMoveTest, UnreachableTargetsAndBadLimitsAreRefused) {
  const auto g = robot1();
  const ScaraJoints from = testing::home(g);
  auto far = plan_joint_move_to(g, limits(), from, ToolPose{{4.2, 0.35, 0.9}, 0.0});
  ASSERT_FALSE(far);
  EXPECT_NE(far.error().message.find("beyond the reach"), std::string::npos) << far.error().message;
  auto low = plan_joint_move_to(g, limits(), from, ToolPose{{3.5, 0.0, 0.7}, 0.0});
  ASSERT_FALSE(low);
  EXPECT_NE(low.error().message.find("joint z"), std::string::npos) << low.error().message;
  auto past = plan_joint_move(g, limits(), from, ScaraJoints{2.7, 0.0, 0.0, 0.0});
  ASSERT_FALSE(past);
  EXPECT_NE(past.error().message.find("θ1"), std::string::npos);
  MotionLimits bad;
  bad.axes[2].jerk = 0.0;
  auto refused = plan_joint_move(g, bad, from, from);
  ASSERT_FALSE(refused);
  EXPECT_NE(refused.error().message.find("z:"), std::string::npos) << refused.error().message;
  EXPECT_FALSE(plan_joint_move(g, limits(), ScaraJoints{std::nan(""), 0.0, 0.0, 0.0}, from));
}

TEST(JointMoveTest, AMoveToWhereTheArmIsTakesNoCycles) {
  const auto g = robot1();
  const ScaraJoints at = testing::home(g);
  auto move = plan_joint_move(g, limits(), at, at);
  ASSERT_TRUE(move);
  EXPECT_EQ(move->cycles(), 0U);
  CspSampler sampler(*move);
  ScaraJoints q{};
  EXPECT_FALSE(sampler.next(q));
}

}  // namespace
}  // namespace sf::motion
