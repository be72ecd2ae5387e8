// The CiA 402 axis API against the emulated drives: enable through the
// controlword state machine, follow a trajectory, recover from a fault.
#include <cmath>

#include <gtest/gtest.h>

#include "segment_bench.hpp"
#include "sf/ethercat/master/cia402.hpp"
#include "sf/ethercat/slave/devices.hpp"

namespace sf::ethercat::master::test {
namespace {

// Cycles until `done` or `limit`; the axis updates after every exchange.
template <typename Done>
int run_until(Bench& b, std::vector<Cia402Axis*> axes, Done&& done, int limit = 1000) {
  for (int i = 1; i <= limit; ++i) {
    b.cycle();
    for (auto* a : axes) {
      a->update();
    }
    if (done()) {
      return i;
    }
  }
  return -1;
}

TEST(Cia402Axis, EnableFollowATrajectoryAndDisable) {
  Bench b("servo:1");
  ASSERT_TRUE(b.master->bring_up().ok());
  auto* drive = b.segment->device<slave::Servo>(0);
  ASSERT_NE(drive, nullptr);
  drive->axis(0).set_position(1000);  // wherever the motor happens to be
  auto axis = Cia402Axis::attach(*b.master, 0);
  ASSERT_TRUE(axis.ok()) << axis.error().describe();

  b.cycle();
  axis->update();
  EXPECT_EQ(axis->state(), cia402::State::SwitchOnDisabled);
  EXPECT_EQ(axis->actual_position(), 1000);

  axis->enable();
  const int steps = run_until(b, {&*axis}, [&] { return axis->enabled(); });
  ASSERT_GT(steps, 0) << "still " << cia402::to_string(axis->state());
  EXPECT_GE(steps, 3);  // shutdown, switch on, enable operation
  EXPECT_EQ(drive->axis(0).state(), slave::Cia402State::OperationEnabled);
  EXPECT_NEAR(drive->axis(0).position(), 1000.0, 1.0);  // enabling did not move it

  // A smooth move 1000 → 21000 counts over one second, one point per cycle.
  std::vector<std::int32_t> trajectory;
  for (int i = 1; i <= 1000; ++i) {
    const double s = 0.5 - 0.5 * std::cos(M_PI * i / 1000.0);
    trajectory.push_back(1000 + static_cast<std::int32_t>(std::lround(20000.0 * s)));
  }
  axis->follow(trajectory);
  double worst = 0;
  for (std::size_t i = 0; i < trajectory.size(); ++i) {
    b.cycle();
    axis->update();
    worst = std::max(worst, std::abs(drive->axis(0).following_error()));
    ASSERT_TRUE(axis->enabled()) << "cycle " << i << ": " << cia402::to_string(axis->state());
  }
  EXPECT_TRUE(axis->trajectory_done());
  EXPECT_EQ(drive->axis(0).target_position(), 21000);
  run_until(
      b, {&*axis}, [] { return false; }, 20);  // let it settle
  EXPECT_NEAR(drive->axis(0).position(), 21000.0, 1.0);
  EXPECT_NEAR(axis->actual_position(), 21000, 1);
  EXPECT_EQ(axis->actual_velocity(), 0);
  EXPECT_LT(worst, 1000.0);

  axis->disable();
  ASSERT_GT(run_until(b, {&*axis}, [&] { return axis->state() == cia402::State::SwitchOnDisabled; }), 0);
}

TEST(Cia402Axis, FaultResetAndEnableAgain) {
  Bench b("servo:1");
  ASSERT_TRUE(b.master->bring_up().ok());
  auto* drive = b.segment->device<slave::Servo>(0);
  auto axis = Cia402Axis::attach(*b.master, 0);
  ASSERT_TRUE(axis.ok());
  axis->enable();
  ASSERT_GT(run_until(b, {&*axis}, [&] { return axis->enabled(); }), 0);

  // An external load pushes the motor away: following error → fault.
  drive->axis(0).set_position(500'000);
  ASSERT_GT(run_until(b, {&*axis}, [&] { return axis->fault(); }), 0);
  EXPECT_EQ(drive->axis(0).error_code(), slave::kErrorFollowing);

  axis->fault_reset();
  ASSERT_GT(run_until(b, {&*axis}, [&] { return axis->enabled(); }), 0) << cia402::to_string(axis->state());
  // Enabled again where the fault left it, without a jump back.
  const double here = drive->axis(0).position();
  EXPECT_GT(here, 400'000.0);
  run_until(
      b, {&*axis}, [] { return false; }, 20);
  EXPECT_NEAR(drive->axis(0).position(), here, 1.0);
  EXPECT_TRUE(axis->enabled());
}

TEST(Cia402Axis, SmartControllerAxesAreIndependent) {
  Bench b("smart-controller:1");
  ASSERT_TRUE(b.master->bring_up().ok());
  auto* drive = b.segment->device<slave::SmartController>(0);
  ASSERT_NE(drive, nullptr);
  std::vector<Cia402Axis> axes;
  for (unsigned n = 0; n < 8; ++n) {
    auto a = Cia402Axis::attach(*b.master, 0, n);
    ASSERT_TRUE(a.ok()) << a.error().describe();
    axes.push_back(std::move(*a));
  }
  axes[3].enable();
  axes[5].enable();
  std::vector<Cia402Axis*> all;
  for (auto& a : axes) {
    all.push_back(&a);
  }
  ASSERT_GT(run_until(b, all, [&] { return axes[3].enabled() && axes[5].enabled(); }), 0);
  EXPECT_FALSE(axes[0].enabled());
  axes[3].set_target_position(300);
  axes[5].set_target_position(-500);
  run_until(
      b, all, [] { return false; }, 50);
  EXPECT_NEAR(drive->axis(3).position(), 300.0, 1.0);
  EXPECT_NEAR(drive->axis(5).position(), -500.0, 1.0);
  EXPECT_NEAR(drive->axis(0).position(), 0.0, 1.0);
  EXPECT_FALSE(Cia402Axis::attach(*b.master, 0, 8).ok());
}

TEST(Cia402Axis, AttachNeedsTheProfileObjects) {
  Bench b("digital-io:1");
  ASSERT_TRUE(b.master->bring_up().ok());
  auto axis = Cia402Axis::attach(*b.master, 0);
  ASSERT_FALSE(axis.ok());
  EXPECT_NE(axis.error().message.find("0x6040"), std::string::npos) << axis.error().message;
}

}  // namespace
}  // namespace sf::ethercat::master::test
