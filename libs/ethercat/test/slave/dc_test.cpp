// Distributed clocks: receive-time latches, system time, the time control
// loop fed by ARMW on 0x0910, SYNC0 (ET1100 datasheet section I §9).
#include <gtest/gtest.h>

#include <cstdlib>

#include "sf/ethercat/slave/devices.hpp"
#include "slave_test_support.hpp"

namespace sf::ethercat::slave {
namespace {

using testing::Harness;

std::uint32_t u32(const Bytes& b, std::size_t at = 0) {
  return load_le<std::uint32_t>(&b[at]);
}
std::uint64_t u64(const Bytes& b, std::size_t at = 0) {
  return load_le<std::uint64_t>(&b[at]);
}

TEST(Dc, WriteTo0x0900LatchesEveryPortWithThePropagationOfTheFrame) {
  SegmentOptions options;
  options.return_delay = std::chrono::nanoseconds{400};  // asymmetric, like real ESCs
  Harness h("servo:3", options);                         // 500 ns forward, 400 ns return, 10 ns cable
  h.assign_stations();
  h.clock.advance(std::chrono::milliseconds{5});
  ASSERT_EQ(h.run(Harness::physical(Command::BWR, 0, reg::kDcReceiveTimePort0, Bytes(4, 0))).wkc, 3);
  std::uint32_t port0[3];
  std::uint32_t port1[3];
  for (std::size_t p = 0; p < 3; ++p) {
    const auto d = h.fprd(Harness::station(p), reg::kDcReceiveTimePort0, 8).data;
    port0[p] = u32(d, 0);
    port1[p] = u32(d, 4);
  }
  const std::uint32_t t0 = 5'000'000;
  EXPECT_EQ(port0[0], t0 + 10);
  EXPECT_EQ(port0[1], t0 + 10 + 510);
  EXPECT_EQ(port0[2], t0 + 10 + 1020);
  // Back: the last slave loops after 500 ns, each hop back costs 10 + 400 ns.
  EXPECT_EQ(port1[1], t0 + 10 + 1020 + 500 + 10);
  EXPECT_EQ(port1[0], port1[1] + 400 + 10);
  EXPECT_EQ(port1[2], 0u);  // closed port: nothing latched
  // The processing unit's time (64 bit) is the port-0 time.
  EXPECT_EQ(u64(h.fprd(Harness::station(1), reg::kDcReceiveTimeProcessingUnit, 8).data), port0[1]);
  // What a master computes: the delay between neighbours from the port differences.
  const std::uint32_t loop0 = port1[0] - port0[0];
  const std::uint32_t loop1 = port1[1] - port0[1];
  EXPECT_EQ((loop0 - loop1) / 2, (500u + 400u) / 2 + 10u);  // (forward + return)/2 + cable
}

TEST(Dc, LocalClockDriftsAndSystemTimeAddsTheOffset) {
  ManualClock clock;
  Segment segment(clock);
  EscOptions fast;
  fast.drift_ppm = 100.0;
  fast.local_time_offset_ns = 1'000'000;
  segment.add(std::make_unique<Servo>(), fast);
  Esc& esc = segment.slave(0);
  EXPECT_EQ(esc.local_time(0), 1'000'000);
  EXPECT_EQ(esc.local_time(1'000'000'000), 1'000'000 + 1'000'100'000);
  // Reading 0x0910 returns local time + 0x0920.
  Harness h("servo:1");
  h.assign_stations();
  h.fpwr_value<std::uint64_t>(Harness::station(0), reg::kDcSystemTimeOffset, 1'000'000'000'000ULL);
  h.clock.advance(std::chrono::microseconds{3});
  const auto sys = u64(h.fprd(Harness::station(0), reg::kDcSystemTime, 8).data);
  EXPECT_EQ(sys, 1'000'000'000'000ULL + 3'000 + 10);
}

// A master's DC start-up: measure delays, set offsets, then distribute the
// reference time with ARMW until the loop has removed the drift.
class DcLoop : public ::testing::Test {
 protected:
  DcLoop() : segment(clock) {
    EscOptions ref;
    ref.drift_ppm = 0.0;
    ref.local_time_offset_ns = 5'000'000'000;
    segment.add(std::make_unique<Servo>(), ref);
    EscOptions slow;
    slow.drift_ppm = -35.0;
    slow.local_time_offset_ns = 123'456'789;
    segment.add(std::make_unique<Servo>(), slow);
    EscOptions fast;
    fast.drift_ppm = 60.0;
    fast.local_time_offset_ns = 42;
    segment.add(std::make_unique<Servo>(), fast);
  }

  Datagram run(Datagram d) {
    Frame f;
    f.datagrams.push_back(std::move(d));
    Bytes bytes = *encode(f);
    EXPECT_TRUE(segment.process(bytes));
    return decode(bytes)->datagrams.front();
  }
  Bytes aprd(std::size_t position, std::uint16_t ado, std::size_t n) {
    return run(Harness::physical(Command::APRD, static_cast<std::uint16_t>(-static_cast<int>(position)), ado,
                                 Bytes(n, 0)))
        .data;
  }
  void apwr(std::size_t position, std::uint16_t ado, Bytes data) {
    EXPECT_EQ(run(Harness::physical(Command::APWR, static_cast<std::uint16_t>(-static_cast<int>(position)),
                                    ado, std::move(data)))
                  .wkc,
              1);
  }

  // Offset and delay compensation as ETG.1020 / SOEM's ecx_configdc do it.
  void compensate() {
    run(Harness::physical(Command::BWR, 0, reg::kDcReceiveTimePort0, Bytes(4, 0)));
    std::int64_t delay = 0;
    const std::uint64_t ref_time = u64(aprd(0, reg::kDcReceiveTimeProcessingUnit, 8));
    std::uint32_t previous_loop = 0;
    for (std::size_t p = 0; p < 3; ++p) {
      const auto ports = aprd(p, reg::kDcReceiveTimePort0, 8);
      const std::uint32_t loop = p < 2 ? u32(ports, 4) - u32(ports, 0) : 0;
      if (p > 0) {
        delay += (previous_loop - loop) / 2;
        apwr(p, reg::kDcSystemTimeDelay, Harness::le<std::uint32_t>(static_cast<std::uint32_t>(delay)));
      }
      previous_loop = loop;
      // System time of this slave at its own latch = reference time + delay.
      const std::uint64_t local = u64(aprd(p, reg::kDcReceiveTimeProcessingUnit, 8));
      apwr(p, reg::kDcSystemTimeOffset,
           Harness::le<std::uint64_t>(ref_time + static_cast<std::uint64_t>(delay) - local));
      apwr(p, reg::kDcSpeedCounterStart, Harness::le<std::uint16_t>(0x1000));
    }
  }

  std::int64_t system_difference(std::size_t p) {
    const std::uint32_t v = u32(aprd(p, reg::kDcSystemTimeDifference, 4));
    const auto magnitude = static_cast<std::int64_t>(v & 0x7FFFFFFFU);
    return (v & 0x80000000U) != 0 ? -magnitude : magnitude;
  }

  ManualClock clock;
  Segment segment;
};

TEST_F(DcLoop, ArmwDistributionRemovesTheDrift) {
  clock.advance(std::chrono::milliseconds{1});
  compensate();
  const auto t = [&] { return std::chrono::nanoseconds(clock.now().time_since_epoch()).count(); };
  // Right after compensation all clocks agree within the delay estimate.
  EXPECT_LT(std::llabs(static_cast<long long>(segment.slave(1).system_time(t()) -
                                              segment.slave(0).system_time(t()))),
            100);
  for (int cycle = 0; cycle < 3000; ++cycle) {
    clock.advance(std::chrono::milliseconds{1});
    auto d = run(Harness::physical(Command::ARMW, 0, reg::kDcSystemTime, Bytes(8, 0)));
    ASSERT_EQ(d.wkc, 3);
  }
  for (std::size_t p = 1; p < 3; ++p) {
    EXPECT_LT(std::llabs(system_difference(p)), 20) << p;
    const auto now = t();
    const auto skew =
        static_cast<std::int64_t>(segment.slave(p).system_time(now) - segment.slave(0).system_time(now));
    EXPECT_LT(std::llabs(skew), 20) << p;
  }
  // The speed counter diff holds the frequency correction (0.1 ppm units):
  // +35 ppm for the slow clock, −60 ppm for the fast one.
  const auto diff1 = load_le<std::int16_t>(aprd(1, reg::kDcSpeedCounterDiff, 2).data());
  const auto diff2 = load_le<std::int16_t>(aprd(2, reg::kDcSpeedCounterDiff, 2).data());
  EXPECT_NEAR(diff1, 350, 5);
  EXPECT_NEAR(diff2, -600, 5);
}

TEST_F(DcLoop, WithoutDistributionTheClocksDriftApart) {
  clock.advance(std::chrono::milliseconds{1});
  compensate();
  clock.advance(std::chrono::seconds{1});
  const auto now = std::chrono::nanoseconds(clock.now().time_since_epoch()).count();
  const auto skew =
      static_cast<std::int64_t>(segment.slave(2).system_time(now) - segment.slave(0).system_time(now));
  EXPECT_NEAR(static_cast<double>(skew), 60'000.0, 200.0);  // 60 ppm of 1 s
}

TEST(Dc, Sync0PulsesFromStartTimeEveryCycle) {
  Harness h("servo:1");
  h.assign_stations();
  const auto st = Harness::station(0);
  // The frame reached the slave 10 ns (one cable) after the clock's "now".
  const auto now = u64(h.fprd(st, reg::kDcSystemTime, 8).data) - 10;
  h.fpwr_value<std::uint32_t>(st, reg::kDcSync0CycleTime, 1'000'000);
  h.fpwr_value<std::uint64_t>(st, reg::kDcStartTimeCyclic, now + 10'000'000);
  h.fpwr(st, reg::kDcActivation, Bytes{0x03});
  EXPECT_EQ(h.fprd(st, reg::kDcActivationStatus, 1).data[0] & 1, 1);  // first pulse pending
  for (int i = 0; i < 20; ++i) {
    h.clock.advance(std::chrono::milliseconds{1});
    h.segment->poll();
  }
  // Pulses at +10, +11, ... +20 ms.
  EXPECT_EQ(h.segment->slave(0).sync0_events(), 11u);
  EXPECT_EQ(h.segment->device<Servo>(0)->sync0_events(), 11u);
  EXPECT_EQ(h.fprd(st, reg::kDcActivationStatus, 1).data[0] & 1, 0);
  EXPECT_EQ(u64(h.fprd(st, reg::kDcStartTimeCyclic, 8).data), now + 21'000'000);  // next pulse
  // Deactivated: no more pulses.
  h.fpwr(st, reg::kDcActivation, Bytes{0x00});
  h.clock.advance(std::chrono::milliseconds{5});
  h.segment->poll();
  EXPECT_EQ(h.segment->slave(0).sync0_events(), 11u);
}

TEST(Dc, Sync0StartTimeInThePastNeverFiresWithoutPlausibilityCheck) {
  Harness h("servo:1");
  h.assign_stations();
  const auto st = Harness::station(0);
  h.clock.advance(std::chrono::milliseconds{50});
  h.fpwr_value<std::uint32_t>(st, reg::kDcSync0CycleTime, 1'000'000);
  h.fpwr_value<std::uint64_t>(st, reg::kDcStartTimeCyclic, 1'000);
  h.fpwr(st, reg::kDcActivation, Bytes{0x03});
  h.clock.advance(std::chrono::milliseconds{10});
  h.segment->poll();
  EXPECT_EQ(h.segment->slave(0).sync0_events(), 0u);
  // With the plausibility check (bit 5) it starts at once.
  h.fpwr(st, reg::kDcActivation, Bytes{0x00});
  h.fpwr(st, reg::kDcActivation, Bytes{0x23});
  h.clock.advance(std::chrono::microseconds{2500});
  h.segment->poll();
  EXPECT_EQ(h.segment->slave(0).sync0_events(), 3u);
}

}  // namespace
}  // namespace sf::ethercat::slave

namespace sf::ethercat::slave {
namespace {

TEST(Dc, SyncTypeDcNeedsSync0BeforeSafeOp) {
  testing::Harness h("servo:1");
  h.assign_stations();
  const auto st = testing::Harness::station(0);
  h.configure_mailbox(0);
  h.configure_process_data(0, 0);
  ASSERT_EQ(h.request(0, AlState::PreOp), AlStatus::of(AlState::PreOp));
  // 0x1C32:01 = 2 (DC SYNC0), written as a master does over CoE; here directly.
  ASSERT_EQ(h.segment->slave(0).objects().download(0x1C32, 1, false, testing::Harness::le<std::uint16_t>(2),
                                                   AlState::PreOp),
            0u);
  EXPECT_EQ(h.request(0, AlState::SafeOp), AlStatus::of(AlState::PreOp, true));
  EXPECT_EQ(h.fprd16(st, reg::kAlStatusCode), 0x0030);
  h.fpwr_value<std::uint32_t>(st, reg::kDcSync0CycleTime, 1'000'000);
  h.fpwr_value<std::uint64_t>(st, reg::kDcStartTimeCyclic, 1'000'000);
  h.fpwr(st, reg::kDcActivation, Bytes{0x03});
  EXPECT_EQ(h.request(0, AlState::SafeOp, true), AlStatus::of(AlState::SafeOp));
}

}  // namespace
}  // namespace sf::ethercat::slave
