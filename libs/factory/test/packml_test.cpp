#include "sf/factory/packml.hpp"

#include <gtest/gtest.h>

namespace sf::factory {
namespace {

using namespace std::chrono_literals;
using S = PackMLState;
using C = PackMLCommand;

TEST(PackMLTest, TheProductionCycle) {
  ManualClock clock;
  PackMLUnit unit(clock);
  EXPECT_EQ(unit.state(), S::Stopped);
  ASSERT_TRUE(unit.command(C::Reset));
  EXPECT_EQ(unit.state(), S::Resetting);
  EXPECT_TRUE(PackMLUnit::acting(unit.state()));
  ASSERT_TRUE(unit.state_complete());
  EXPECT_EQ(unit.state(), S::Idle);
  ASSERT_TRUE(unit.command(C::Start));
  ASSERT_TRUE(unit.state_complete());
  EXPECT_EQ(unit.state(), S::Execute);
  ASSERT_TRUE(unit.state_complete());
  EXPECT_EQ(unit.state(), S::Completing);
  ASSERT_TRUE(unit.state_complete());
  EXPECT_EQ(unit.state(), S::Complete);
  ASSERT_TRUE(unit.command(C::Reset));
  EXPECT_EQ(unit.state(), S::Resetting);
}

// A controller that starts by itself takes the operator's path, a command per call, and leaves
// the acting states to the controller's work.
TEST(PackMLTest, AStartWithoutAnOperatorResetsThenStarts) {
  ManualClock clock;
  PackMLUnit unit(clock);
  EXPECT_FALSE(unit.advance_to_execute());
  EXPECT_EQ(unit.state(), S::Resetting);
  EXPECT_FALSE(unit.advance_to_execute());  // Resetting is the controller's to complete
  EXPECT_EQ(unit.state(), S::Resetting);
  ASSERT_TRUE(unit.state_complete());
  EXPECT_FALSE(unit.advance_to_execute());
  EXPECT_EQ(unit.state(), S::Starting);
  ASSERT_TRUE(unit.state_complete());
  EXPECT_TRUE(unit.advance_to_execute());
  EXPECT_EQ(operator_stop_reason(C::Hold)->message, "operator: Hold");
  EXPECT_EQ(operator_stop_reason(C::Hold)->id, kStopOperator);
  EXPECT_FALSE(operator_stop_reason(C::Start));
}

TEST(PackMLTest, HoldAndUnholdComeBackToExecute) {
  ManualClock clock;
  PackMLUnit unit(clock, S::Execute);
  ASSERT_TRUE(unit.command(C::Hold, StopReason{7, "operator hold", {}}));
  ASSERT_TRUE(unit.state_complete());
  EXPECT_EQ(unit.state(), S::Held);
  EXPECT_EQ(unit.status().stop_reason->message, "operator hold");
  EXPECT_EQ(unit.status().stop_reason->at, clock.utc_now());
  ASSERT_TRUE(unit.command(C::Unhold));
  ASSERT_TRUE(unit.state_complete());
  EXPECT_EQ(unit.state(), S::Execute);
  ASSERT_TRUE(unit.command(C::Suspend));
  ASSERT_TRUE(unit.state_complete());
  EXPECT_EQ(unit.state(), S::Suspended);
  ASSERT_TRUE(unit.command(C::Unsuspend));
  ASSERT_TRUE(unit.state_complete());
  EXPECT_EQ(unit.state(), S::Execute);
}

TEST(PackMLTest, CommandsTheStateDoesNotAcceptAreRefusedAndChangeNothing) {
  ManualClock clock;
  PackMLUnit unit(clock);
  for (C c : {C::Start, C::Stop, C::Hold, C::Unhold, C::Suspend, C::Unsuspend, C::Clear}) {
    auto st = unit.command(c);
    ASSERT_FALSE(st) << to_string(c);
    EXPECT_EQ(st.error().code, Errc::state);
    EXPECT_NE(st.error().message.find("not allowed in Stopped"), std::string::npos);
    EXPECT_EQ(unit.state(), S::Stopped);
  }
  EXPECT_FALSE(unit.state_complete());  // Stopped has no work to complete
  EXPECT_TRUE(unit.accepts(C::Reset));
  EXPECT_TRUE(unit.accepts(C::Abort));
}

TEST(PackMLTest, AFaultAbortsAndClearLeadsBackToStopped) {
  ManualClock clock;
  PackMLUnit unit(clock, S::Execute);
  unit.fault(StopReason{0x7310, "axis 2: overspeed", {}});
  EXPECT_EQ(unit.state(), S::Aborting);
  unit.fault(StopReason{1, "second fault", {}});  // already aborting: the first reason stays
  EXPECT_EQ(unit.status().stop_reason->id, 0x7310);
  ASSERT_TRUE(unit.state_complete());
  EXPECT_EQ(unit.state(), S::Aborted);
  EXPECT_FALSE(unit.command(C::Reset));
  ASSERT_TRUE(unit.command(C::Clear));
  ASSERT_TRUE(unit.state_complete());
  EXPECT_EQ(unit.state(), S::Stopped);
}

TEST(PackMLTest, StopIsAcceptedFromEveryStateButTheStoppedAndAbortedOnes) {
  for (auto s : {S::Idle, S::Starting, S::Execute, S::Completing, S::Complete, S::Resetting, S::Holding,
                 S::Held, S::Unholding, S::Suspending, S::Suspended, S::Unsuspending}) {
    ManualClock clock;
    PackMLUnit unit(clock, s);
    EXPECT_TRUE(unit.command(C::Stop)) << to_string(s);
    EXPECT_EQ(unit.state(), S::Stopping);
  }
  for (auto s : {S::Stopped, S::Stopping, S::Aborting, S::Aborted, S::Clearing}) {
    ManualClock clock;
    PackMLUnit unit(clock, s);
    EXPECT_FALSE(unit.command(C::Stop)) << to_string(s);
  }
}

TEST(PackMLTest, TimeInStateAndCountersAddUp) {
  ManualClock clock;
  PackMLUnit unit(clock, S::Idle);
  clock.advance(2s);
  ASSERT_TRUE(unit.command(C::Start));
  clock.advance(1s);
  ASSERT_TRUE(unit.state_complete());
  clock.advance(5s);
  unit.count(true);
  unit.count(false);
  const auto s = unit.status();
  EXPECT_EQ(s.time_in_state[static_cast<std::size_t>(S::Idle)], 2s);
  EXPECT_EQ(s.time_in_state[static_cast<std::size_t>(S::Starting)], 1s);
  EXPECT_EQ(s.time_in_state[static_cast<std::size_t>(S::Execute)], 5s);  // the current state, so far
  EXPECT_EQ(s.produced, 2U);
  EXPECT_EQ(s.defective, 1U);
  EXPECT_FALSE(unit.set_mode(PackMLMode::Manual));  // not while producing
  ASSERT_TRUE(unit.command(C::Stop));
  ASSERT_TRUE(unit.state_complete());
  ASSERT_TRUE(unit.set_mode(PackMLMode::Maintenance));
  EXPECT_EQ(unit.status().mode, PackMLMode::Maintenance);
}

}  // namespace
}  // namespace sf::factory
