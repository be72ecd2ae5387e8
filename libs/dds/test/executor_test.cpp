#include "sf/dds/executor.hpp"

#include <atomic>
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

}  // namespace
}  // namespace sf::dds
