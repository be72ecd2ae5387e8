// Distributed clocks: with every slave's oscillator drifting differently,
// the master's delay/offset setup, static drift compensation and the FRMW in
// every cycle bring every slave's system time difference (0x092C) under 1 µs,
// and the slaves' system times agree with the reference's.
#include <cmath>

#include <gtest/gtest.h>

#include "segment_bench.hpp"

namespace sf::ethercat::master::test {
namespace {

std::int64_t segment_ns(const ManualClock& clock) {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(clock.now().time_since_epoch()).count();
}

class DistributedClocks : public ::testing::TestWithParam<const char*> {};

TEST_P(DistributedClocks, SystemTimesConvergeUnderOneMicrosecond) {
  MasterOptions o;  // the default 15 000 static drift frames
  slave::SegmentOptions so;
  so.drift_spread_ppm = 80.0;  // each oscillator off by up to ±80 ppm
  so.esc.local_time_offset_ns = 123'456'789;
  so.seed = 7;
  Bench b(GetParam(), o, so);
  auto st = b.master->bring_up();
  ASSERT_TRUE(st.ok()) << st.error().describe();
  auto& m = *b.master;
  ASSERT_EQ(m.dc_reference(), std::optional<std::size_t>{0});

  // Delays grow along the line (ETG.1000.4 §9.1.3.4).
  for (std::size_t p = 1; p < m.slave_count(); ++p) {
    EXPECT_GT(m.slave_info(p).dc.delay_ns, m.slave_info(p - 1).dc.delay_ns) << "slave " << p;
  }

  // Two seconds of 1 ms cycles, each with the FRMW of 0x0910.
  for (int i = 0; i < 2000; ++i) {
    ASSERT_TRUE(b.cycle().ok()) << "cycle " << i;
  }
  EXPECT_NE(m.dc_time(), 0U);
  for (std::size_t p = 0; p < m.slave_count(); ++p) {
    auto diff = m.read_dc_difference(p);
    ASSERT_TRUE(diff.ok()) << diff.error().describe();
    EXPECT_LT(std::abs(*diff), 1000) << "slave " << p << " 0x092C = " << *diff << " ns";
  }
  // The clocks themselves agree: at one instant every slave's system time is
  // the reference's, within 1 µs.
  const auto now = segment_ns(b.clock);
  const auto reference = b.segment->slave(0).system_time(now);
  for (std::size_t p = 1; p < b.segment->size(); ++p) {
    const auto t = b.segment->slave(p).system_time(now);
    const auto d = static_cast<std::int64_t>(t - reference);
    EXPECT_LT(std::abs(d), 1000) << "slave " << p << " is " << d << " ns off the reference";
  }
  // And the reference runs on the master's time (ns since 2000).
  const auto since_2000 = b.clock.utc_now() - std::chrono::sys_seconds{std::chrono::seconds{946684800}};
  const auto master_ns = std::chrono::duration_cast<std::chrono::nanoseconds>(since_2000).count();
  EXPECT_LT(std::abs(static_cast<std::int64_t>(reference) - master_ns), 10'000'000);
}

INSTANTIATE_TEST_SUITE_P(Segments, DistributedClocks,
                         ::testing::Values("servo:3", "smart-controller:2,digital-io:4,servo:2"));

TEST(DistributedClocksDrift, WithoutCompensationTheClocksDriftApart) {
  // The control experiment: the same drifts, DC set up, but then no FRMW
  // (slaves without a cyclic frame) for two seconds.
  slave::SegmentOptions so;
  so.drift_spread_ppm = 80.0;
  so.seed = 7;
  Bench b("servo:3", quick_options(), so);
  ASSERT_TRUE(b.master->bring_up().ok());
  const auto start = segment_ns(b.clock);
  const auto spread = [&](std::int64_t at) {
    std::int64_t worst = 0;
    for (std::size_t p = 1; p < b.segment->size(); ++p) {
      worst = std::max(worst, std::abs(static_cast<std::int64_t>(b.segment->slave(p).system_time(at) -
                                                                 b.segment->slave(0).system_time(at))));
    }
    return worst;
  };
  EXPECT_LT(spread(start), 1000);
  EXPECT_GT(spread(start + 2'000'000'000), 1000);
}

TEST(DistributedClocksSync0, Sync0PulsesStartTogether) {
  MasterOptions o = quick_options();
  o.sync0_cycle = std::chrono::milliseconds{1};
  Bench b("servo:2", o);
  ASSERT_TRUE(b.master->bring_up().ok());
  for (int i = 0; i < 500; ++i) {
    ASSERT_TRUE(b.cycle().ok());
  }
  const auto first = b.segment->slave(0).sync0_events();
  EXPECT_GT(first, 300U);
  EXPECT_NEAR(static_cast<double>(b.segment->slave(1).sync0_events()), static_cast<double>(first), 2.0);
}

// Loses FRMW frames (the drift compensation's) in bursts: `burst` in a row out of every `every`,
// as a master on a loaded host sees when the answers come after its frame timeout.
class FrmwBurstLoss final : public Link {
 public:
  FrmwBurstLoss(Link& inner, std::size_t burst, std::size_t every)
      : inner_(inner), burst_(burst), every_(every) {}
  Status send(ByteSpan frame) override {
    const std::size_t command_at = kEthernetHeaderSize + kEcatHeaderSize;
    const bool frmw =
        frame.size() > command_at && frame[command_at] == static_cast<std::uint8_t>(Command::FRMW);
    if (lossy && frmw && frmw_sent_++ % every_ < burst_) {
      ++lost;
      return {};
    }
    return inner_.send(frame);
  }
  Result<std::size_t> receive(MutableByteSpan buf, std::chrono::nanoseconds timeout) override {
    return inner_.receive(buf, timeout);
  }
  [[nodiscard]] MacAddress mac() const override { return inner_.mac(); }
  [[nodiscard]] std::string name() const override { return "frmw-burst-loss"; }
  bool lossy = true;
  std::size_t lost = 0;

 private:
  Link& inner_;
  std::size_t burst_;
  std::size_t every_;
  std::size_t frmw_sent_ = 0;
};

TEST(DistributedClocksDrift, LostCompensationFramesCostOnlyTheirSamples) {
  // Bursts longer than the bus's resends (3) used to end the bring-up.
  slave::SegmentOptions so;
  so.drift_spread_ppm = 80.0;
  so.seed = 7;
  Bench b("servo:3", quick_options(), so);
  FrmwBurstLoss lossy(*b.link, 6, 400);
  Master master(lossy, b.clock, quick_options());
  auto st = master.bring_up();
  ASSERT_TRUE(st.ok()) << st.error().describe();
  EXPECT_GE(lossy.lost, 6U * (2000 / 400));
  lossy.lossy = false;
  for (int i = 0; i < 2000; ++i) {
    b.clock.advance(std::chrono::milliseconds{1});
    ASSERT_TRUE(master.exchange().ok()) << "cycle " << i;
    master.maintain();
  }
  for (std::size_t p = 0; p < master.slave_count(); ++p) {
    auto diff = master.read_dc_difference(p);
    ASSERT_TRUE(diff.ok()) << diff.error().describe();
    EXPECT_LT(std::abs(*diff), 1000) << "slave " << p << " 0x092C = " << *diff << " ns";
  }
}

TEST(DistributedClocksDrift, AReferenceThatStopsAnsweringEndsTheBringUp) {
  Bench b("servo:2");
  FrmwBurstLoss silent(*b.link, 1, 1);  // every FRMW lost
  Master master(silent, b.clock, quick_options());
  auto st = master.bring_up();
  ASSERT_FALSE(st.ok());
  EXPECT_EQ(st.error().code, Errc::timeout);
  EXPECT_NE(st.error().message.find("DC static drift compensation"), std::string::npos) << st.error().message;
  EXPECT_NE(st.error().message.find("51 lost in a row"), std::string::npos) << st.error().message;
}

}  // namespace
}  // namespace sf::ethercat::master::test
