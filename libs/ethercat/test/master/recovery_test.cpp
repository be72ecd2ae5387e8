// Running with faults: frame loss, a slave that drops out and comes back,
// and a master that stops (the slaves' watchdogs take over).
#include <gtest/gtest.h>

#include "segment_bench.hpp"
#include "sf/ethercat/slave/devices.hpp"

namespace sf::ethercat::master::test {
namespace {

TEST(Recovery, OnePercentFrameLossKeepsOpAndIsCounted) {
  Bench b("smart-controller:1,digital-io:4,servo:3");
  ASSERT_TRUE(b.master->bring_up().ok());
  auto& m = *b.master;
  m.statistics().reset();
  b.segment->set_drop_probability(0.01);
  std::size_t received = 0;
  for (int i = 0; i < 10'000; ++i) {
    const auto r = b.cycle();
    if (r.received) {
      ++received;
      EXPECT_EQ(r.wkc, r.expected_wkc) << "cycle " << i;
    }
  }
  b.segment->set_drop_probability(0.0);
  const auto& stats = m.statistics();
  EXPECT_EQ(stats.cycles, 10'000U);
  EXPECT_EQ(stats.lost_frames, 10'000U - received);
  // About 1 % (seeded, so repeatable): between 0.5 % and 2 %.
  EXPECT_GT(stats.lost_frames, 50U);
  EXPECT_LT(stats.lost_frames, 200U);
  EXPECT_EQ(stats.wkc_errors, 0U);
  EXPECT_TRUE(m.lost_slaves().empty());
  for (std::size_t p = 0; p < b.segment->size(); ++p) {
    EXPECT_EQ(b.segment->slave(p).state(), AlState::Op) << "slave " << p;
  }
}

TEST(Recovery, DisconnectedSlaveIsReportedAndComesBackToOp) {
  Bench b("smart-controller:1,digital-io:4,servo:3");
  ASSERT_TRUE(b.master->bring_up().ok());
  auto& m = *b.master;
  std::vector<SlaveEvent> events;
  m.on_slave_event([&](const SlaveEvent& e) { events.push_back(e); });
  auto out5 = m.slave(4).entry(0x7000, 0);  // a digital IO behind the one we pull
  ASSERT_TRUE(out5.ok());
  for (int i = 0; i < 100; ++i) {
    ASSERT_TRUE(b.cycle().ok());
  }

  b.segment->disconnect(2);
  std::size_t bad = 0;
  for (int i = 0; i < 200; ++i) {
    m.slave(4).set<std::uint8_t>(*out5, static_cast<std::uint8_t>(i));
    const auto r = b.cycle();
    bad += r.ok() ? 0U : 1U;
    // The others keep running: outputs still reach slave 4.
    EXPECT_EQ(b.segment->device<slave::DigitalIo>(4)->outputs(), static_cast<std::uint8_t>(i));
  }
  EXPECT_EQ(bad, 200U);  // the WKC misses slave 2's share every cycle
  EXPECT_EQ(m.lost_slaves(), std::vector<std::size_t>{2});
  const auto diagnosis = m.diagnose();
  ASSERT_EQ(diagnosis.size(), 1U);
  EXPECT_EQ(diagnosis[0].position, 2U);
  EXPECT_TRUE(diagnosis[0].lost);
  EXPECT_NE(diagnosis[0].message.find("slave 2"), std::string::npos) << diagnosis[0].message;
  for (std::size_t p = 0; p < b.segment->size(); ++p) {
    if (p != 2) {
      EXPECT_EQ(b.segment->slave(p).state(), AlState::Op) << "slave " << p;
    }
  }

  b.segment->reconnect(2);  // power-on defaults: INIT, station address 0
  EXPECT_EQ(b.segment->slave(2).station_address(), 0);
  int cycles = 0;
  while (!m.lost_slaves().empty() || !m.last_exchange().ok()) {
    ASSERT_LT(++cycles, 1000) << "slave 2 did not come back";
    b.cycle();
  }
  EXPECT_EQ(b.segment->slave(2).station_address(), 0x1003);
  // The application heard about it: lost, found, recovered — all slave 2.
  ASSERT_EQ(events.size(), 3U);
  EXPECT_EQ(events[0].kind, SlaveEvent::Kind::lost);
  EXPECT_EQ(events[1].kind, SlaveEvent::Kind::found);
  EXPECT_EQ(events[2].kind, SlaveEvent::Kind::recovered);
  for (const auto& e : events) {
    EXPECT_EQ(e.position, 2U) << e.message;
  }
  for (std::size_t p = 0; p < b.segment->size(); ++p) {
    EXPECT_EQ(b.segment->slave(p).state(), AlState::Op) << "slave " << p;
  }
  // And it does its part again.
  auto out2 = m.slave(2).entry(0x7000, 0);
  ASSERT_TRUE(out2.ok());
  m.slave(2).set<std::uint8_t>(*out2, 0x5A);
  ASSERT_TRUE(b.cycle().ok());
  EXPECT_EQ(b.segment->device<slave::DigitalIo>(2)->outputs(), 0x5A);
  EXPECT_TRUE(m.diagnose().empty());
}

TEST(Recovery, ASegmentSilentForLessThanThreeDiagnosesIsNotLost) {
  // Frames that do not come back for a few cycles (an EtherCAT-in-UDP peer on a loaded host):
  // the master diagnoses every maintenance interval (5 ms) but calls a slave lost only after
  // three silent diagnoses in a row.
  Bench b("digital-io:2,servo:1");
  ASSERT_TRUE(b.master->bring_up().ok());
  auto& m = *b.master;
  std::vector<SlaveEvent> events;
  m.on_slave_event([&](const SlaveEvent& e) { events.push_back(e); });
  for (int i = 0; i < 20; ++i) {
    ASSERT_TRUE(b.cycle().ok());
  }
  b.segment->set_drop_probability(1.0);
  for (int i = 0; i < 7; ++i) {
    EXPECT_FALSE(b.cycle().received);
  }
  b.segment->set_drop_probability(0.0);
  for (int i = 0; i < 20; ++i) {
    b.cycle();
  }
  EXPECT_TRUE(m.last_exchange().ok());
  EXPECT_TRUE(events.empty()) << events.front().message;
  // Silent for longer: every slave lost, as before.
  b.segment->set_drop_probability(1.0);
  for (int i = 0; i < 30; ++i) {
    b.cycle();
  }
  EXPECT_EQ(m.lost_slaves(), (std::vector<std::size_t>{0, 1, 2}));
}

TEST(Recovery, TwoSlavesOutBackInAnyOrder) {
  Bench b("digital-io:4,servo:3");
  ASSERT_TRUE(b.master->bring_up().ok());
  auto& m = *b.master;
  b.segment->disconnect(1);
  b.segment->disconnect(5);
  for (int i = 0; i < 50; ++i) {
    b.cycle();
  }
  EXPECT_EQ(m.lost_slaves(), (std::vector<std::size_t>{1, 5}));
  // The later one first: found between its known neighbours 4 and 6.
  b.segment->reconnect(5);
  int cycles = 0;
  while (m.lost_slaves() != std::vector<std::size_t>{1}) {
    ASSERT_LT(++cycles, 1000) << "slave 5 did not come back";
    b.cycle();
  }
  EXPECT_EQ(b.segment->slave(5).station_address(), 0x1006);
  EXPECT_EQ(b.segment->slave(5).state(), AlState::Op);
  b.segment->reconnect(1);
  cycles = 0;
  while (!m.lost_slaves().empty() || !m.last_exchange().ok()) {
    ASSERT_LT(++cycles, 1000) << "slave 1 did not come back";
    b.cycle();
  }
  for (std::size_t p = 0; p < b.segment->size(); ++p) {
    EXPECT_EQ(b.segment->slave(p).station_address(), 0x1001 + p);
    EXPECT_EQ(b.segment->slave(p).state(), AlState::Op) << "slave " << p;
  }
}

TEST(Recovery, WholeSegmentLostAndBack) {
  Bench b("digital-io:2,servo:1");
  ASSERT_TRUE(b.master->bring_up().ok());
  auto& m = *b.master;
  for (std::size_t p = 0; p < 3; ++p) {
    b.segment->disconnect(p);
  }
  for (int i = 0; i < 20; ++i) {
    EXPECT_FALSE(b.cycle().received);
  }
  EXPECT_EQ(m.lost_slaves(), (std::vector<std::size_t>{0, 1, 2}));
  for (std::size_t p = 0; p < 3; ++p) {
    b.segment->reconnect(p);
  }
  int cycles = 0;
  while (!m.lost_slaves().empty() || !m.last_exchange().ok()) {
    ASSERT_LT(++cycles, 1000) << "the segment did not come back";
    b.cycle();
  }
  for (std::size_t p = 0; p < 3; ++p) {
    EXPECT_EQ(b.segment->slave(p).station_address(), 0x1001 + p);
    EXPECT_EQ(b.segment->slave(p).state(), AlState::Op) << "slave " << p;
  }
}

TEST(Recovery, DcReferenceLostAndBack) {
  Bench b("servo:3");
  ASSERT_TRUE(b.master->bring_up().ok());
  auto& m = *b.master;
  for (int i = 0; i < 100; ++i) {
    ASSERT_TRUE(b.cycle().ok());
  }
  b.segment->disconnect(0);
  for (int i = 0; i < 50; ++i) {
    b.cycle();
  }
  EXPECT_EQ(m.lost_slaves(), std::vector<std::size_t>{0});
  b.segment->reconnect(0);
  int cycles = 0;
  while (!m.lost_slaves().empty() || !m.last_exchange().ok()) {
    ASSERT_LT(++cycles, 1000) << "the reference did not come back";
    b.cycle();
  }
  for (int i = 0; i < 1000; ++i) {
    ASSERT_TRUE(b.cycle().ok());
  }
  for (std::size_t p = 0; p < m.slave_count(); ++p) {
    auto diff = m.read_dc_difference(p);
    ASSERT_TRUE(diff.ok());
    EXPECT_LT(std::abs(*diff), 1000) << "slave " << p;
  }
}

TEST(Recovery, StoppedMasterTripsTheWatchdogsSafeOutputs) {
  Bench b("digital-io:2,servo:1");
  ASSERT_TRUE(b.master->bring_up().ok());
  auto& m = *b.master;
  auto out = m.slave(0).entry(0x7000, 0);
  ASSERT_TRUE(out.ok());
  m.slave(0).set<std::uint8_t>(*out, 0xA5);
  for (int i = 0; i < 10; ++i) {
    ASSERT_TRUE(b.cycle().ok());
  }
  ASSERT_EQ(b.segment->device<slave::DigitalIo>(0)->outputs(), 0xA5);
  EXPECT_EQ(m.watchdog_expired(0), std::optional<bool>{false});

  // The master stops; time goes on (default watchdog: 100 ms).
  b.clock.advance(std::chrono::milliseconds{150});
  b.segment->poll();
  for (std::size_t p = 0; p < b.segment->size(); ++p) {
    const auto status = b.segment->slave(p).al_status();
    EXPECT_EQ(status.state(), AlState::SafeOp) << "slave " << p;
    EXPECT_TRUE(status.error) << "slave " << p;
    EXPECT_EQ(b.segment->slave(p).al_status_code(), 0x001B) << "slave " << p;
  }
  EXPECT_EQ(b.segment->device<slave::DigitalIo>(0)->outputs(), 0);  // safe state
  for (std::size_t p = 0; p < b.segment->size(); ++p) {
    EXPECT_TRUE(b.segment->slave(p).device().outputs_safe()) << "slave " << p;
  }

  // The master reports it by position and code...
  const auto diagnosis = m.diagnose();
  ASSERT_EQ(diagnosis.size(), 3U);
  EXPECT_EQ(diagnosis[0].al_status_code, 0x001B);
  EXPECT_NE(diagnosis[0].message.find("Sync manager watchdog"), std::string::npos) << diagnosis[0].message;
  // ...and, running again, acknowledges and returns them to OP.
  int cycles = 0;
  do {
    ASSERT_LT(++cycles, 1000);
    b.cycle();
  } while (!m.last_exchange().ok() ||
           m.last_exchange().al_state_or != static_cast<std::uint16_t>(AlState::Op));
  EXPECT_GT(cycles, 1);  // the first cycle found them in SAFEOP + ERROR
  ASSERT_TRUE(b.cycle().ok());
  EXPECT_EQ(b.segment->device<slave::DigitalIo>(0)->outputs(), 0xA5);
  EXPECT_EQ(m.watchdog_expired(0), std::optional<bool>{false});
}

}  // namespace
}  // namespace sf::ethercat::master::test
