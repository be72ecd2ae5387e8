// The master against a segment served by its own thread over an in-memory
// link pair, on the real clock: frames come back asynchronously, as from a
// NIC. (No timing is asserted; generous timeouts absorb a loaded machine.)
#include <gtest/gtest.h>

#include "segment_bench.hpp"
#include "sf/ethercat/master/cyclic_runner.hpp"
#include "sf/ethercat/slave/devices.hpp"

namespace sf::ethercat::master::test {
namespace {

TEST(ThreadedSegment, BringUpAndCycleOnTheSteadyClock) {
  auto& clock = SteadyClock::instance();
  auto segment = slave::Segment::create("servo:1,digital-io:2", clock);
  ASSERT_TRUE(segment.ok());
  auto pair = make_memory_link_pair();
  slave::SegmentRunner server(**segment, *pair.b, std::chrono::microseconds{200});
  ASSERT_TRUE(server.start().ok());

  MasterOptions o;
  o.bus.frame_timeout = std::chrono::milliseconds{50};
  o.dc_static_drift_frames = 200;
  o.dc_static_drift_interval = std::chrono::microseconds{10};
  Master master(*pair.a, clock, o);
  auto st = master.bring_up();
  ASSERT_TRUE(st.ok()) << st.error().describe();

  CyclicOptions co;
  co.period = std::chrono::microseconds{500};
  co.realtime = false;
  CyclicRunner runner(master, co);
  auto out = master.slave(2).entry(0x7000, 0);
  ASSERT_TRUE(out.ok());
  std::size_t ok = 0;
  runner.run_cycles(200, [&](Master& m, const ExchangeResult& r) {
    ok += r.ok() ? 1U : 0U;
    m.slave(2).set<std::uint8_t>(*out, 0x3C);
  });
  EXPECT_GT(ok, 0U);  // how many depends on the machine's load, not on the master
  server.stop();
  auto lock = (*segment)->lock();
  EXPECT_EQ((*segment)->device<slave::DigitalIo>(2)->outputs(), 0x3C);
  EXPECT_EQ((*segment)->slave(0).state(), AlState::Op);
}

}  // namespace
}  // namespace sf::ethercat::master::test
