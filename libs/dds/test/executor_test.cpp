#include "sf/dds/executor.hpp"

#include <atomic>
#include <string>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

namespace sf::dds {
namespace {

TEST(Executor, RunsPostedTasksInOrderOnTheCallingThread) {
  Executor ex;
  std::vector<int> order;
  const auto caller = std::this_thread::get_id();
  bool same_thread = true;
  for (int i = 0; i < 5; ++i) {
    ex.post([&, i] {
      order.push_back(i);
      same_thread = same_thread && std::this_thread::get_id() == caller;
    });
  }
  EXPECT_EQ(ex.pending(), 5U);
  EXPECT_EQ(ex.run_pending(), 5U);
  EXPECT_EQ(order, (std::vector<int>{0, 1, 2, 3, 4}));
  EXPECT_TRUE(same_thread);
  EXPECT_EQ(ex.run_pending(), 0U);
}

TEST(Executor, TasksPostedByTasksRunInTheNextRound) {
  Executor ex;
  int inner = 0;
  ex.post([&] { ex.post([&] { ++inner; }); });
  EXPECT_EQ(ex.run_pending(), 1U);
  EXPECT_EQ(inner, 0);
  EXPECT_EQ(ex.run_pending(), 1U);
  EXPECT_EQ(inner, 1);
}

TEST(Executor, WaitReturnsWhenAnotherThreadPosts) {
  Executor ex;
  std::atomic<bool> ran{false};
  std::thread t{[&] { ex.post([&] { ran = true; }); }};
  // Generous bound: the assertion is that the task arrives, not how fast.
  while (ex.pending() == 0) {
    ex.wait_for(std::chrono::seconds{5});
  }
  t.join();
  ex.run_pending();
  EXPECT_TRUE(ran.load());
}

TEST(Executor, SpinningWaitStillSeesTasksFromOtherThreads) {
  Executor ex;
  ex.set_spin(std::chrono::milliseconds{5});
  std::atomic<bool> ran{false};
  std::thread t{[&] { ex.post([&] { ran = true; }); }};
  while (ex.pending() == 0) {
    ex.wait_for(std::chrono::seconds{5});
  }
  t.join();
  EXPECT_EQ(ex.run_pending(), 1U);
  EXPECT_TRUE(ran.load());
  // Nothing queued: the spin ends and the wait times out.
  EXPECT_FALSE(ex.wait_for(std::chrono::milliseconds{1}));
}

TEST(Executor, NotifyWakesWithoutATask) {
  Executor ex;
  ex.notify();
  EXPECT_FALSE(ex.wait_for(std::chrono::hours{1}));  // returns at once: notified, nothing queued
}

// --- inline delivery ----------------------------------------------------------

TEST(ExecutorInline, ATaskRunsAtOnceOnThePostingThread) {
  Executor ex;
  ex.set_inline(true);
  std::thread::id ran_on;
  std::thread t{[&] { ex.post([&] { ran_on = std::this_thread::get_id(); }); }};
  const auto poster = t.get_id();
  t.join();
  EXPECT_EQ(ran_on, poster);
  EXPECT_EQ(ex.pending(), 0U);
}

TEST(ExecutorInline, WhileTheStrandIsHeldTasksWaitForTheApplicationThread) {
  Executor ex;
  ex.set_inline(true);
  bool ran = false;
  {
    const auto strand = ex.hold();
    std::thread t{[&] { ex.post([&] { ran = true; }); }};
    t.join();  // the post returned without blocking on the strand
    EXPECT_FALSE(ran);
    EXPECT_EQ(ex.pending(), 1U);
  }
  EXPECT_EQ(ex.run_pending(), 1U);
  EXPECT_TRUE(ran);
}

TEST(ExecutorInline, APostFromATaskIsQueuedNotRunInsideIt) {
  Executor ex;
  ex.set_inline(true);
  std::vector<std::string> order;
  ex.post([&] {
    order.emplace_back("outer begins");
    ex.post([&] { order.emplace_back("inner"); });
    order.emplace_back("outer ends");
  });
  // The outer one ran at once; the inner one waits for the application thread.
  EXPECT_EQ(order, (std::vector<std::string>{"outer begins", "outer ends"}));
  EXPECT_EQ(ex.pending(), 1U);
  EXPECT_EQ(ex.run_pending(), 1U);
  EXPECT_EQ(order, (std::vector<std::string>{"outer begins", "outer ends", "inner"}));
}

TEST(ExecutorInline, ATaskDoesNotOvertakeQueuedOnes) {
  Executor ex;
  std::vector<int> order;
  ex.post([&] { order.push_back(1); });  // queued: inline delivery is off
  ex.set_inline(true);
  ex.post([&] { order.push_back(2); });  // queued behind the first, not run now
  EXPECT_TRUE(order.empty());
  EXPECT_EQ(ex.run_pending(), 2U);
  ex.post([&] { order.push_back(3); });  // queue empty: inline
  EXPECT_EQ(order, (std::vector<int>{1, 2, 3}));
}

TEST(ExecutorInline, TheWakeCheckDecidesWhetherTheApplicationThreadWakes) {
  Executor ex;
  ex.set_inline(true);
  bool wake = false;
  {
    const auto strand = ex.hold();
    ex.set_wake_check([&] { return wake; });
  }
  using Clock = std::chrono::steady_clock;
  ex.post([] {});
  // Not woken: the wait runs its full length (a condition variable wait with a
  // predicate does not return early without a notification).
  auto t0 = Clock::now();
  EXPECT_FALSE(ex.wait_for(std::chrono::milliseconds{20}));
  EXPECT_GE(Clock::now() - t0, std::chrono::milliseconds{20});
  wake = true;
  ex.post([] {});
  // Woken: returns (nothing queued) long before the bound.
  t0 = Clock::now();
  EXPECT_FALSE(ex.wait_for(std::chrono::seconds{30}));
  EXPECT_LT(Clock::now() - t0, std::chrono::seconds{30});
}

TEST(ExecutorInline, TurnedOffUnderTheStrandNothingRunsInlineAnyMore) {
  Executor ex;
  ex.set_inline(true);
  {
    const auto strand = ex.hold();
    ex.set_inline(false);
  }
  std::atomic<int> ran{0};
  std::thread t{[&] { ex.post([&] { ++ran; }); }};
  t.join();
  EXPECT_EQ(ran.load(), 0);
  EXPECT_EQ(ex.run_pending(), 1U);
  EXPECT_EQ(ran.load(), 1);
}

TEST(ExecutorInline, ManyPostingThreadsNeverRunTasksConcurrently) {
  Executor ex;
  ex.set_inline(true);
  int inside = 0;  // guarded by the strand: a data race here is what ASan/TSan builds would flag
  int overlaps = 0;
  int total = 0;
  std::vector<std::thread> threads;
  for (int i = 0; i < 4; ++i) {
    threads.emplace_back([&] {
      for (int k = 0; k < 2000; ++k) {
        ex.post([&] {
          overlaps += inside++ > 0 ? 1 : 0;
          ++total;
          --inside;
        });
      }
    });
  }
  for (int k = 0; k < 200; ++k) {
    const auto strand = ex.hold();  // the application thread takes turns too
    ex.run_pending();
  }
  for (auto& t : threads) {
    t.join();
  }
  ex.run_pending();
  EXPECT_EQ(overlaps, 0);
  EXPECT_EQ(total, 8000);
}

}  // namespace
}  // namespace sf::dds
