// The buffer survives a killed process: a child process buffers (or forwards)
// and is SIGKILLed at a chosen moment; the parent opens the same buffer and
// database and checks that every sample is there exactly once, in order.
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include "hooked_store.hpp"
#include "make_sample.hpp"
#include "sf/historian/buffered_store.hpp"
#include "temp_dir.hpp"

namespace sf::historian {
namespace {

using namespace std::chrono_literals;
using test::HookedStore;

const Timestamp kCrashT0 = from_micros(1'763'683'200'000'000);
const SeriesInfo kSeries{"opc.tcp://m1:4840", "ns=2;s=Crash"};
constexpr int kBatches = 40;
constexpr int kPerBatch = 25;

std::vector<Sample> batch(int n) {
  std::vector<Sample> out;
  const auto id = series_id(kSeries.server, kSeries.node_id);
  for (int i = 0; i < kPerBatch; ++i) {
    const int k = n * kPerBatch + i;
    out.push_back(test::make_sample(id, kCrashT0 + k * 1ms, kCrashT0,
                                    Value{std::string(static_cast<std::size_t>(k % 7), 'x')}));
  }
  return out;
}

class CrashTest : public ::testing::Test {
 protected:
  std::string db_url() const { return "sqlite:" + (dir_.path() / "history.db").string(); }
  BufferOptions buffer() const { return BufferOptions{dir_.path() / "buffer"}; }

  // Runs `child` in a forked process, which must die by SIGKILL.
  template <typename F>
  void run_child_until_killed(F child) {
    const pid_t pid = ::fork();
    ASSERT_GE(pid, 0);
    if (pid == 0) {
      child();
      ::_exit(3);  // should not get here
    }
    int status = 0;
    ASSERT_EQ(::waitpid(pid, &status, 0), pid);
    ASSERT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == SIGKILL) << "child status " << status;
  }

  void expect_all_exactly_once() {
    auto store = BufferedStore::open(db_url(), buffer(), clock_);
    ASSERT_TRUE(store.ok()) << store.error().describe();
    auto flushed = (*store)->flush();
    ASSERT_TRUE(flushed.ok()) << flushed.error().describe();
    EXPECT_EQ((*store)->stats().buffered_records, 0U);
    std::vector<Sample> expected;
    for (int n = 0; n < kBatches; ++n) {
      const auto b = batch(n);
      expected.insert(expected.end(), b.begin(), b.end());
    }
    auto rows =
        (*store)->read_raw(series_id(kSeries.server, kSeries.node_id), kCrashT0, kCrashT0 + 1h, 100'000);
    ASSERT_TRUE(rows.ok()) << rows.error().describe();
    ASSERT_EQ(rows->size(), expected.size());
    EXPECT_TRUE(*rows == expected);
  }

  test::TempDir dir_;
  ManualClock clock_;
};

TEST_F(CrashTest, WhatWasBufferedSurvivesAKill) {
  run_child_until_killed([&] {
    // The database is unreachable for the child's whole life.
    auto store = BufferedStore::open([] { return open_store("sqlite:/nonexistent-directory/h.db"); },
                                     buffer(), clock_);
    if (!store || !(*store)->register_series(kSeries)) {
      ::_exit(1);
    }
    for (int n = 0; n < kBatches; ++n) {
      if (!(*store)->append(batch(n))) {
        ::_exit(2);
      }
    }
    ::raise(SIGKILL);
  });
  expect_all_exactly_once();
}

TEST_F(CrashTest, AKillWhileForwardingNeitherLosesNorDuplicates) {
  run_child_until_killed([&] {
    bool up = false;
    int commits = 0;
    auto store = BufferedStore::open(
        [&]() -> Result<std::unique_ptr<Store>> {
          auto db = open_store(db_url());
          if (!db) {
            return db.error();
          }
          return std::unique_ptr<Store>{std::make_unique<HookedStore>(
              std::move(*db),
              [&](std::string_view) { return up ? std::nullopt : std::optional{test::unreachable()}; },
              [&](std::string_view op) -> std::optional<Error> {
                // Dies after the third forwarded batch is committed, before
                // the buffer's cursor records it: that batch comes again.
                if (op == "append" && ++commits == 3) {
                  ::raise(SIGKILL);
                }
                return std::nullopt;
              })};
        },
        BufferOptions{dir_.path() / "buffer", 8U << 20U, true, OnCorruption::salvage, 1ULL << 30U, 200ms, 30s,
                      static_cast<std::size_t>(kPerBatch * 4)},
        clock_);
    if (!store || !(*store)->register_series(kSeries)) {
      ::_exit(1);
    }
    for (int n = 0; n < kBatches; ++n) {
      if (!(*store)->append(batch(n))) {
        ::_exit(2);
      }
    }
    up = true;
    clock_.advance(1s);
    (void)(*store)->flush();
    ::_exit(4);  // not reached: the hook kills the process
  });
  expect_all_exactly_once();
}

}  // namespace
}  // namespace sf::historian
