// CyclicRunner: absolute deadlines, the per-cycle callback, statistics, and
// the thread that runs until stopped.
#include "sf/ethercat/master/cyclic_runner.hpp"

#include <thread>

#include <gtest/gtest.h>

#include "segment_bench.hpp"
#include "sf/ethercat/slave/devices.hpp"

namespace sf::ethercat::master::test {
namespace {

CyclicOptions test_options() {
  CyclicOptions o;
  o.period = std::chrono::microseconds{500};
  o.realtime = false;  // no mlockall in a test process
  return o;
}

TEST(CyclicRunner, CyclesOnAbsoluteDeadlines) {
  Bench b("digital-io:2");
  ASSERT_TRUE(b.master->bring_up().ok());
  b.master->statistics().reset();
  CyclicRunner runner(*b.master, test_options());
  const auto start = b.clock.now();
  std::size_t calls = 0;
  runner.run_cycles(1000, [&](Master& m, const ExchangeResult& r) {
    ++calls;
    EXPECT_TRUE(r.ok());
    // Outputs written in the callback go out with the next cycle.
    auto out = m.slave(1).entry(0x7000, 0);
    m.slave(1).set<std::uint8_t>(*out, static_cast<std::uint8_t>(calls));
  });
  EXPECT_EQ(calls, 1000U);
  // 1000 periods of 500 µs: the ManualClock jumped to each deadline.
  EXPECT_EQ(b.clock.now() - start, std::chrono::milliseconds{500});
  const auto stats = runner.statistics();
  EXPECT_EQ(stats.cycles, 1000U);
  EXPECT_EQ(stats.jitter.count(), 1000U);
  EXPECT_EQ(stats.jitter.max(), std::chrono::nanoseconds{0});
  EXPECT_EQ(stats.wkc_errors, 0U);
  EXPECT_EQ(b.segment->device<slave::DigitalIo>(1)->outputs(), static_cast<std::uint8_t>(999));
}

TEST(CyclicRunner, OverrunSkipsMissedDeadlines) {
  Bench b("digital-io:1");
  ASSERT_TRUE(b.master->bring_up().ok());
  CyclicRunner runner(*b.master, test_options());
  const auto start = b.clock.now();
  runner.run_cycles(1, [&](Master&, const ExchangeResult&) {
    b.clock.advance(std::chrono::microseconds{2200});  // the application took 4+ periods
  });
  runner.run_cycles(1);
  // Deadlines stay on the 500 µs grid: start + 500, then (after the
  // overrun to +2700) the next free slot at +3000.
  EXPECT_EQ(b.clock.now() - start, std::chrono::microseconds{3000});
}

TEST(CyclicRunner, ThreadRunsUntilStopped) {
  Bench b("digital-io:2");
  ASSERT_TRUE(b.master->bring_up().ok());
  b.master->statistics().reset();
  CyclicRunner runner(*b.master, test_options());
  std::atomic<std::uint64_t> calls{0};
  ASSERT_TRUE(runner.start([&](Master&, const ExchangeResult&) { ++calls; }).ok());
  EXPECT_TRUE(runner.running());
  EXPECT_FALSE(runner.start().ok());  // only one thread
  while (calls.load() < 500) {
    std::this_thread::yield();
  }
  runner.stop();
  EXPECT_FALSE(runner.running());
  const auto stats = runner.statistics();
  EXPECT_GE(stats.cycles, 500U);
  EXPECT_EQ(stats.cycles, calls.load());
  EXPECT_EQ(stats.wkc_errors, 0U);
  EXPECT_EQ(stats.lost_frames, 0U);
  // After stop() the master is the caller's again.
  EXPECT_TRUE(b.master->exchange().ok());
}

TEST(CyclicRunner, SdoTransfersWhileTheCycleRuns) {
  Bench b("servo:1,digital-io:1");
  ASSERT_TRUE(b.master->bring_up().ok());
  b.master->statistics().reset();
  CyclicRunner runner(*b.master, test_options());
  std::atomic<std::uint64_t> cycles{0};
  ASSERT_TRUE(runner.start([&](Master&, const ExchangeResult&) { ++cycles; }).ok());
  // Mailbox traffic from this thread interleaves with the cyclic frames:
  // the bus is locked per frame, not per transfer.
  std::uint32_t last = 0;
  for (int i = 0; i < 50 || cycles.load() < 200; ++i) {
    auto name = b.master->sdo_upload(0, 0x1008, 0);
    ASSERT_TRUE(name.ok()) << name.error().describe();
    last = static_cast<std::uint32_t>(1000 + i);
    ASSERT_TRUE(b.master->sdo_write<std::uint32_t>(0, 0x607F, 0, last).ok());
  }
  runner.stop();
  const auto stats = runner.statistics();
  EXPECT_EQ(stats.wkc_errors, 0U);
  EXPECT_EQ(stats.lost_frames, 0U);
  EXPECT_EQ(b.segment->slave(0).state(), AlState::Op);
  auto v = b.master->sdo_read<std::uint32_t>(0, 0x607F, 0);
  ASSERT_TRUE(v.ok());
  EXPECT_EQ(*v, last);
}

}  // namespace
}  // namespace sf::ethercat::master::test
