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

TEST(ScaledClock, SleepUntilReachesItsOwnDeadlineAndRunsAhead) {
  ScaledClock clock(50.0);
  const auto real_start = std::chrono::steady_clock::now();
  const auto start = clock.now();
  clock.sleep_until(start + 100ms);  // 2 ms of real time
  EXPECT_GE(clock.now(), start + 100ms);
  // Scaled time ran at least as far as the real time times the factor allows.
  const auto real = std::chrono::steady_clock::now() - real_start;
  EXPECT_GE(clock.now() - start, std::chrono::duration_cast<Clock::duration>(real * 49.0));
  EXPECT_GE(clock.utc_now() - std::chrono::system_clock::now(), std::chrono::milliseconds{90});
}

}  // namespace
}  // namespace sf
