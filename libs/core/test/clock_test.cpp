#include "sf/core/clock.hpp"

#include <thread>

#include <gtest/gtest.h>

namespace sf {
namespace {

using namespace std::chrono_literals;

TEST(ManualClock, MovesOnlyWhenTold) {
  ManualClock clock;
  const auto t0 = clock.now();
  EXPECT_EQ(clock.now(), t0);
  clock.advance(1500us);
  EXPECT_EQ(clock.now() - t0, 1500us);
  EXPECT_EQ(clock.utc_now() - ManualClock{}.utc_now(), 1500us);
}

TEST(ManualClock, SleepUntilJumpsForwardNeverBack) {
  ManualClock clock;
  clock.sleep_until(clock.now() + 10ms);
  EXPECT_EQ(clock.now().time_since_epoch(), 10ms);
  clock.sleep_until(Clock::time_point{5ms});
  EXPECT_EQ(clock.now().time_since_epoch(), 10ms);
  clock.set(Clock::time_point{2ms});
  EXPECT_EQ(clock.now().time_since_epoch(), 2ms);
}

TEST(ManualClock, ConcurrentAdvanceIsNotLost) {
  ManualClock clock;
  std::thread a([&] {
    for (int i = 0; i < 10000; ++i)
      clock.advance(1ns);
  });
  std::thread b([&] {
    for (int i = 0; i < 10000; ++i)
      clock.advance(1ns);
  });
  a.join();
  b.join();
  EXPECT_EQ(clock.now().time_since_epoch(), 20000ns);
}

TEST(SteadyClock, SleepUntilReachesDeadline) {
  auto& clock = SteadyClock::instance();
  const auto deadline = clock.now() + 2ms;
  clock.sleep_until(deadline);
  EXPECT_GE(clock.now(), deadline);
}

TEST(SteadyClock, IsMonotonic) {
  auto& clock = SteadyClock::instance();
  auto prev = clock.now();
  for (int i = 0; i < 1000; ++i) {
    const auto t = clock.now();
    ASSERT_GE(t, prev);
    prev = t;
  }
}

}  // namespace
}  // namespace sf
