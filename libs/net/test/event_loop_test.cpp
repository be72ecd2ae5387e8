#include "sf/net/event_loop.hpp"

#include <gtest/gtest.h>

#include <atomic>
#include <condition_variable>
#include <mutex>
#include <thread>
#include <vector>

namespace sf::net {
namespace {

using namespace std::chrono_literals;

// Stops the loop after a generous time so a broken test fails instead of hanging.
void add_watchdog(EventLoop& loop, bool& fired) {
  loop.add_timer(10s, [&] {
    fired = true;
    loop.stop();
  });
}

TEST(EventLoop, TimersRunInDeadlineOrder) {
  EventLoop loop;
  bool watchdog = false;
  add_watchdog(loop, watchdog);
  std::vector<int> order;
  loop.add_timer(30ms, [&] {
    order.push_back(30);
    loop.stop();
  });
  loop.add_timer(10ms, [&] { order.push_back(10); });
  loop.add_timer(20ms, [&] { order.push_back(20); });
  loop.add_timer(0ms, [&] { order.push_back(0); });
  loop.run();
  EXPECT_FALSE(watchdog);
  EXPECT_EQ(order, (std::vector<int>{0, 10, 20, 30}));
}

// Timers read the loop's clock: an hour on a ManualClock passes at once.
TEST(EventLoop, TimersFollowTheLoopsClock) {
  ManualClock clock;
  EventLoop loop(clock);
  std::vector<int> order;
  loop.add_timer(1h, [&] {
    order.push_back(2);
    loop.stop();
  });
  loop.add_periodic(30min, [&] { order.push_back(1); });
  loop.add_timer(0ms, [&] {
    order.push_back(0);
    clock.advance(1h);
  });
  loop.run();
  EXPECT_EQ(order, (std::vector<int>{0, 1, 2}));
  EXPECT_EQ(&loop.clock(), &clock);
}

TEST(EventLoop, EqualDeadlinesRunInInsertionOrder) {
  EventLoop loop;
  std::vector<int> order;
  for (int i = 0; i < 5; ++i) {
    loop.add_timer(0ms, [&, i] { order.push_back(i); });
  }
  loop.add_timer(5ms, [&] { loop.stop(); });
  loop.run();
  EXPECT_EQ(order, (std::vector<int>{0, 1, 2, 3, 4}));
}

TEST(EventLoop, CancelledTimerDoesNotRun) {
  EventLoop loop;
  bool ran = false;
  const auto id = loop.add_timer(5ms, [&] { ran = true; });
  loop.add_timer(20ms, [&] { loop.stop(); });
  loop.cancel_timer(id);
  loop.cancel_timer(12345);  // unknown ids are ignored
  loop.run();
  EXPECT_FALSE(ran);
}

TEST(EventLoop, TimerCancelsAnotherDueAtTheSameTime) {
  EventLoop loop;
  bool second_ran = false;
  EventLoop::TimerId second = 0;
  loop.add_timer(1ms, [&] { loop.cancel_timer(second); });
  second = loop.add_timer(1ms, [&] { second_ran = true; });
  loop.add_timer(20ms, [&] { loop.stop(); });
  loop.run();
  EXPECT_FALSE(second_ran);
}

TEST(EventLoop, PeriodicTimerRepeatsUntilItCancelsItself) {
  EventLoop loop;
  bool watchdog = false;
  add_watchdog(loop, watchdog);
  int count = 0;
  EventLoop::TimerId id = 0;
  id = loop.add_periodic(2ms, [&] {
    if (++count == 5) {
      loop.cancel_timer(id);
      loop.add_timer(20ms, [&] { loop.stop(); });
    }
  });
  loop.run();
  EXPECT_FALSE(watchdog);
  EXPECT_EQ(count, 5);
}

TEST(EventLoop, PostFromOtherThreadsRunsEverythingInFifoOrderPerThread) {
  LoopThread thread;
  constexpr int kThreads = 4;
  constexpr int kPosts = 2000;
  std::vector<std::vector<int>> seen(kThreads);  // touched on the loop thread only
  std::mutex mutex;
  std::condition_variable cv;
  int done = 0;
  std::vector<std::thread> posters;
  for (int t = 0; t < kThreads; ++t) {
    posters.emplace_back([&, t] {
      for (int i = 0; i < kPosts; ++i) {
        thread.loop().post([&, t, i] {
          EXPECT_TRUE(thread.loop().in_loop_thread());
          seen[static_cast<std::size_t>(t)].push_back(i);
          if (i == kPosts - 1) {
            const std::lock_guard lock(mutex);
            ++done;
            cv.notify_all();
          }
        });
      }
    });
  }
  for (auto& p : posters) {
    p.join();
  }
  std::unique_lock lock(mutex);
  ASSERT_TRUE(cv.wait_for(lock, 10s, [&] { return done == kThreads; }));
  lock.unlock();
  thread.run_sync([&] {
    for (const auto& s : seen) {
      ASSERT_EQ(s.size(), static_cast<std::size_t>(kPosts));
      for (int i = 0; i < kPosts; ++i) {
        EXPECT_EQ(s[static_cast<std::size_t>(i)], i);
      }
    }
  });
  EXPECT_FALSE(thread.loop().in_loop_thread());
}

TEST(EventLoop, RunSyncWaitsForTheLoop) {
  LoopThread thread;
  std::atomic<int> value{0};
  thread.run_sync([&] { value = 42; });
  EXPECT_EQ(value.load(), 42);
}

TEST(EventLoop, StopFromAnotherThreadEndsRun) {
  EventLoop loop;
  // Whether stop() lands before or during run(), run() returns.
  std::thread stopper([&] { loop.stop(); });
  loop.run();
  stopper.join();
  SUCCEED();
}

}  // namespace
}  // namespace sf::net
