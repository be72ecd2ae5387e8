// Segment spec parsing, topology faults, frame loss, SegmentLink and
// SegmentRunner.
#include <gtest/gtest.h>

#include <thread>

#include "sf/ethercat/slave/devices.hpp"
#include "slave_test_support.hpp"

namespace sf::ethercat::slave {
namespace {

using testing::Harness;

TEST(SegmentSpec, ParsesKindsAndCounts) {
  auto items = parse_segment_spec(" smart-controller:2, digital-io:4 ,servo");
  ASSERT_TRUE(items.ok()) << items.error().describe();
  ASSERT_EQ(items->size(), 3u);
  EXPECT_EQ((*items)[0], (SegmentSpecItem{"smart-controller", 2}));
  EXPECT_EQ((*items)[1], (SegmentSpecItem{"digital-io", 4}));
  EXPECT_EQ((*items)[2], (SegmentSpecItem{"servo", 1}));
}

TEST(SegmentSpec, ErrorsNameTheProblem) {
  const std::pair<const char*, const char*> cases[] = {
      {"", "empty"},
      {"  ", "empty"},
      {"servo:0", "at least 1"},
      {"servo:x", "not a number"},
      {"servo:2x", "not a number"},
      {"servo:", "not a number"},
      {"robot:1", "unknown device kind \"robot\""},
      {"servo:1,,servo:1", "item 2: empty"},
      {":3", "missing device kind"},
      {"servo:70000", "exceeds"},
      {"servo:40000,digital-io:40000", "more than"},
  };
  for (const auto& [spec, message] : cases) {
    auto r = parse_segment_spec(spec);
    ASSERT_FALSE(r.ok()) << spec;
    EXPECT_NE(r.error().message.find(message), std::string::npos) << spec << ": " << r.error().message;
    EXPECT_EQ(r.error().code, Errc::invalid_argument);
  }
  ManualClock clock;
  EXPECT_FALSE(Segment::create("servo:1,robot", clock).ok());
}

// The one table of device models: every row makes a device of its own kind, and the names the
// spec parser and the CLI's help list are the table's.
TEST(DeviceModels, EveryModelMakesADeviceOfItsKind) {
  const auto models = device_models();
  ASSERT_EQ(models.size(), device_kinds().size());
  for (std::size_t i = 0; i < models.size(); ++i) {
    EXPECT_EQ(models[i].name, device_kinds()[i]);
    EXPECT_FALSE(models[i].summary.empty());
    auto device = make_device(models[i].name);
    ASSERT_TRUE(device.ok()) << models[i].name;
    EXPECT_EQ((*device)->kind(), models[i].name);
    EXPECT_TRUE(parse_segment_spec(std::string(models[i].name) + ":2").ok());
  }
  const auto unknown = make_device("robot");
  ASSERT_FALSE(unknown.ok());
  EXPECT_EQ(unknown.error().code, Errc::not_found);
}

TEST(Segment, CreatesDevicesInOrderWithCountingSerials) {
  ManualClock clock;
  SegmentOptions options;
  options.device.serial = 100;
  auto segment = Segment::create("servo:2,digital-io:1", clock, options);
  ASSERT_TRUE(segment.ok());
  ASSERT_EQ((*segment)->size(), 3u);
  EXPECT_EQ((*segment)->slave(0).device().kind(), "servo");
  EXPECT_EQ((*segment)->slave(2).device().kind(), "digital-io");
  EXPECT_EQ((*segment)->slave(1).device().sii().identity.serial, 101u);
}

TEST(Segment, DisconnectDropsTheSlaveOutAndReconnectRestoresPowerOnDefaults) {
  Harness h("servo:3");
  h.assign_stations();
  h.configure_mailbox(1);
  ASSERT_EQ(h.request(1, AlState::PreOp), AlStatus::of(AlState::PreOp));
  h.segment->disconnect(1);
  EXPECT_FALSE(h.segment->connected(1));
  EXPECT_EQ(h.run(Harness::physical(Command::BRD, 0, reg::kType, Bytes(1))).wkc, 2);
  // Positions shift: position 1 is now the third slave.
  auto d = h.run(Harness::physical(Command::APRD, 0xFFFF, reg::kStationAddress, Bytes(2)));
  EXPECT_EQ(load_le<std::uint16_t>(d.data.data()), Harness::station(2));
  EXPECT_EQ(h.fprd(Harness::station(1), reg::kType, 1).wkc, 0);
  // Disconnecting the last one closes the loop at the new last slave.
  h.segment->disconnect(2);
  EXPECT_TRUE(DlStatus{h.fprd16(Harness::station(0), reg::kDlStatus)}.loop_closed(1));
  h.segment->reconnect(2);
  h.segment->reconnect(1);
  EXPECT_EQ(h.run(Harness::physical(Command::BRD, 0, reg::kType, Bytes(1))).wkc, 3);
  EXPECT_EQ(h.segment->slave(1).station_address(), 0);
  EXPECT_EQ(h.segment->slave(1).state(), AlState::Init);
  EXPECT_EQ(h.segment->slave(1).read8(reg::sync_manager(0) + reg::kSmActivate), 0);
  EXPECT_EQ(h.segment->slave(2).station_address(), 0);
}

TEST(Segment, NoConnectedSlaveMeansTheFrameIsLost) {
  Harness h("digital-io:1");
  h.segment->disconnect(0);
  EXPECT_TRUE(h.run(Harness::physical(Command::BRD, 0, 0, Bytes(1))).data.empty());
  EXPECT_EQ(h.segment->counters().lost, 1u);
}

TEST(Segment, DropProbabilityLosesFramesBeforeOrAfterTheSlaves) {
  SegmentOptions options;
  options.drop_probability = 1.0;
  Harness h("servo:1", options);
  for (int i = 0; i < 20; ++i) {
    EXPECT_TRUE(
        h.run(Harness::physical(Command::BRW, 0, 0x0F80, Harness::le<std::uint32_t>(1))).data.empty());
  }
  EXPECT_EQ(h.segment->counters().dropped, 20u);
  // Some frames were lost on the way back: the slave had seen them.
  EXPECT_EQ(h.segment->slave(0).read32(0x0F80), 1u);
  h.segment->set_drop_probability(0.0);
  EXPECT_EQ(h.run(Harness::physical(Command::BRD, 0, 0, Bytes(1))).wkc, 1);
}

TEST(SegmentLink, SendProcessesAndReceiveReturnsTheAnswer) {
  ManualClock clock;
  auto segment = Segment::create("servo:2", clock);
  ASSERT_TRUE(segment.ok());
  SegmentLink link(**segment);
  Frame f;
  f.source = link.mac();
  f.datagrams.push_back(Harness::physical(Command::BRD, 0, reg::kType, Bytes(1)));
  const Bytes out = *encode(f);
  ASSERT_TRUE(link.send(out).ok());
  Bytes in(kMaxFrameSize);
  auto n = link.receive(in, std::chrono::milliseconds{1});
  ASSERT_TRUE(n.ok());
  ASSERT_EQ(*n, out.size());
  in.resize(*n);
  auto back = decode(in);
  ASSERT_TRUE(back.ok());
  EXPECT_EQ(back->datagrams[0].wkc, 2);
  EXPECT_EQ(back->source[0], link.mac()[0] | 0x02);
  // Nothing more in flight.
  EXPECT_EQ(*link.receive(in, std::chrono::milliseconds{1}), 0u);
  // A buffer too small for the frame is an error, not a truncation.
  ASSERT_TRUE(link.send(out).ok());
  Bytes tiny(10);
  EXPECT_FALSE(link.receive(tiny, std::chrono::milliseconds{1}).ok());
}

TEST(SegmentRunner, ServesASegmentOnAMemoryLink) {
  ManualClock clock;
  auto segment = Segment::create("servo:1,digital-io:2", clock);
  ASSERT_TRUE(segment.ok());
  auto pair = make_memory_link_pair();
  SegmentRunner runner(**segment, *pair.b, std::chrono::milliseconds{1});
  ASSERT_TRUE(runner.start().ok());
  Frame f;
  f.source = pair.a->mac();
  f.datagrams.push_back(Harness::physical(Command::BRD, 0, reg::kType, Bytes(1)));
  ASSERT_TRUE(pair.a->send(*encode(f)).ok());
  Bytes in(kMaxFrameSize);
  auto n = pair.a->receive(in, std::chrono::seconds{5});
  runner.stop();
  ASSERT_TRUE(n.ok());
  ASSERT_GT(*n, 0u);
  in.resize(*n);
  EXPECT_EQ(decode(in)->datagrams[0].wkc, 3);
  const auto counters = runner.counters();
  EXPECT_EQ(counters.frames, 1u);
  EXPECT_EQ(counters.answered, 1u);
  EXPECT_EQ(counters.errors, 0u);
}

TEST(SegmentRunner, RunOnceAnswersInTheCallersThread) {
  ManualClock clock;
  auto segment = Segment::create("digital-io:1", clock);
  auto pair = make_memory_link_pair();
  SegmentRunner runner(**segment, *pair.b);
  EXPECT_FALSE(*runner.run_once(std::chrono::milliseconds{1}));  // nothing there
  Frame f;
  f.datagrams.push_back(Harness::physical(Command::BRD, 0, reg::kType, Bytes(1)));
  ASSERT_TRUE(pair.a->send(*encode(f)).ok());
  EXPECT_TRUE(*runner.run_once(std::chrono::milliseconds{100}));
  Bytes in(kMaxFrameSize);
  EXPECT_GT(*pair.a->receive(in, std::chrono::milliseconds{100}), 0u);
}

}  // namespace
}  // namespace sf::ethercat::slave
