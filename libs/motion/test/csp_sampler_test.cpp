#include "sf/motion/csp_sampler.hpp"

#include <gtest/gtest.h>

#include "sf/motion/testing/scara_cell.hpp"

namespace sf::motion {
namespace {

TEST(CspSamplerTest, OneSetPointPerCycleEndingAtTheTargetThenNothing) {
  const auto g = testing::robot1();
  const ScaraJoints start = testing::home(g);
  auto line = plan_line(g, MotionLimits{}, start, {testing::kGummy, 0.0});
  ASSERT_TRUE(line);
  CspSampler sampler(*line);
  EXPECT_EQ(sampler.cycles(), line->cycles());
  ScaraJoints q{};
  std::size_t n = 0;
  CartesianPath::Cursor cursor;
  ScaraJoints previous = start;
  while (sampler.next(q)) {
    ++n;
    EXPECT_EQ(sampler.cycle(), n);
    // The same as evaluating the path at n cycles from scratch.
    auto direct = line->joints_at(static_cast<double>(n) * line->cycle(), previous, cursor);
    ASSERT_TRUE(direct);
    if (n < line->cycles()) {
      EXPECT_EQ(q, *direct);
    }
    previous = q;
  }
  EXPECT_EQ(n, line->cycles());
  EXPECT_TRUE(sampler.done());
  EXPECT_EQ(q, line->end_joints());
  const ScaraJoints before = q;
  EXPECT_FALSE(sampler.next(q));
  EXPECT_EQ(q, before);
  EXPECT_TRUE(sampler.fault());
}

TEST(CspSamplerTest, AJointMoveSamplesItsProfiles) {
  const auto g = testing::robot1();
  const ScaraJoints from = testing::home(g);
  auto move = plan_joint_move_to(g, MotionLimits{}, from, ToolPose{testing::kChocolate, 1.0});
  ASSERT_TRUE(move);
  CspSampler sampler(*move);
  ScaraJoints q{};
  ASSERT_TRUE(sampler.next(q));
  EXPECT_EQ(q, move->at(move->cycle()).position);
  while (sampler.next(q)) {
  }
  EXPECT_EQ(q, move->to());
  EXPECT_EQ(sampler.cycle(), move->cycles());
}

}  // namespace
}  // namespace sf::motion
