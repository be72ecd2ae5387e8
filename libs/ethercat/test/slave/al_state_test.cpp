// The EtherCAT state machine: transitions, refused ones with their AL status
// codes, error acknowledge, SyncManager checks, watchdog (ETG.1000.6 §6.4).
#include <gtest/gtest.h>

#include "sf/ethercat/al_status_codes.hpp"
#include "sf/ethercat/slave/devices.hpp"
#include "slave_test_support.hpp"

namespace sf::ethercat::slave {
namespace {

using testing::Harness;

constexpr std::uint16_t al_code(AlStatusCode c) {
  return static_cast<std::uint16_t>(c);
}

TEST(AlState, StartsInInitWithoutError) {
  Harness h("servo:1");
  h.assign_stations();
  EXPECT_EQ(h.fprd16(Harness::station(0), reg::kAlStatus), 0x0001);
  EXPECT_EQ(h.fprd16(Harness::station(0), reg::kAlStatusCode), 0);
}

TEST(AlState, PreOpNeedsAValidMailboxConfiguration) {
  Harness h("servo:1");
  h.assign_stations();
  auto s = h.request(0, AlState::PreOp);
  EXPECT_EQ(s, AlStatus::of(AlState::Init, true));
  EXPECT_EQ(h.fprd16(Harness::station(0), reg::kAlStatusCode),
            al_code(AlStatusCode::InvalidMailboxConfiguration));
  // Acknowledge with a correct configuration: PREOP, error gone.
  h.configure_mailbox(0);
  s = h.request(0, AlState::PreOp, true);
  EXPECT_EQ(s, AlStatus::of(AlState::PreOp));
  EXPECT_EQ(h.fprd16(Harness::station(0), reg::kAlStatusCode), 0);
}

TEST(AlState, MailboxWithWrongDirectionOrTooSmallIsRefused) {
  Harness h("servo:1");
  h.assign_stations();
  h.write_sm(0, 0, 0x1000, 128, 0x22);  // master→slave mailbox configured as read
  h.write_sm(0, 1, 0x1080, 128, 0x22);
  EXPECT_EQ(h.request(0, AlState::PreOp), AlStatus::of(AlState::Init, true));
  h.write_sm(0, 0, 0x1000, 128, 0x26, false);
  h.write_sm(0, 0, 0x1000, 8, 0x26);  // too small for any CoE message
  EXPECT_EQ(h.request(0, AlState::PreOp, true), AlStatus::of(AlState::Init, true));
  EXPECT_EQ(h.fprd16(Harness::station(0), reg::kAlStatusCode),
            al_code(AlStatusCode::InvalidMailboxConfiguration));
}

TEST(AlState, InvalidAndUnknownRequestsGetTheirCodes) {
  Harness h("servo:1");
  h.assign_stations();
  EXPECT_EQ(h.request(0, AlState::Op), AlStatus::of(AlState::Init, true));
  EXPECT_EQ(h.fprd16(Harness::station(0), reg::kAlStatusCode),
            al_code(AlStatusCode::InvalidRequestedStateChange));
  EXPECT_EQ(h.request(0, AlState::SafeOp, true), AlStatus::of(AlState::Init, true));
  EXPECT_EQ(h.fprd16(Harness::station(0), reg::kAlStatusCode),
            al_code(AlStatusCode::InvalidRequestedStateChange));
  // State 0x7 does not exist.
  h.fpwr_value<std::uint16_t>(Harness::station(0), reg::kAlControl, 0x0017);
  EXPECT_EQ(h.fprd16(Harness::station(0), reg::kAlStatus), 0x0011);
  EXPECT_EQ(h.fprd16(Harness::station(0), reg::kAlStatusCode), al_code(AlStatusCode::UnknownRequestedState));
}

TEST(AlState, HigherStatesWaitForTheErrorAcknowledge) {
  Harness h("servo:1");
  h.assign_stations();
  h.request(0, AlState::PreOp);  // refused: no mailbox yet
  h.configure_mailbox(0);
  // Without acknowledge the request is ignored, the error stays.
  EXPECT_EQ(h.request(0, AlState::PreOp), AlStatus::of(AlState::Init, true));
  // Acknowledging the current state only clears the error.
  EXPECT_EQ(h.request(0, AlState::Init, true), AlStatus::of(AlState::Init));
  EXPECT_EQ(h.request(0, AlState::PreOp), AlStatus::of(AlState::PreOp));
}

TEST(AlState, BootstrapOnlyWithAMailboxAndOnlyBackToInit) {
  Harness h("digital-io:1,servo:1");
  h.assign_stations();
  EXPECT_EQ(h.request(0, AlState::Bootstrap), AlStatus::of(AlState::Init, true));
  EXPECT_EQ(h.fprd16(Harness::station(0), reg::kAlStatusCode), al_code(AlStatusCode::BootstrapNotSupported));
  h.configure_mailbox(1);
  EXPECT_EQ(h.request(1, AlState::Bootstrap), AlStatus::of(AlState::Bootstrap));
  EXPECT_EQ(h.request(1, AlState::PreOp), AlStatus::of(AlState::Bootstrap, true));
  EXPECT_EQ(h.fprd16(Harness::station(1), reg::kAlStatusCode),
            al_code(AlStatusCode::InvalidRequestedStateChange));
  EXPECT_EQ(h.request(1, AlState::Init), AlStatus::of(AlState::Init, true));
  EXPECT_EQ(h.request(1, AlState::Init, true), AlStatus::of(AlState::Init));
}

TEST(AlState, SafeOpChecksTheProcessDataSyncManagers) {
  Harness h("servo:1");
  h.assign_stations();
  h.configure_mailbox(0);
  ASSERT_EQ(h.request(0, AlState::PreOp), AlStatus::of(AlState::PreOp));
  // No process-data SyncManagers at all: invalid output configuration.
  EXPECT_EQ(h.request(0, AlState::SafeOp), AlStatus::of(AlState::PreOp, true));
  EXPECT_EQ(h.fprd16(Harness::station(0), reg::kAlStatusCode),
            al_code(AlStatusCode::InvalidOutputConfiguration));
  // Outputs right (6 bytes), inputs one byte short.
  h.write_sm(0, 2, kOutputsStart, 6, 0x64);
  h.write_sm(0, 3, kInputsStart, 9, 0x20);
  EXPECT_EQ(h.request(0, AlState::SafeOp, true), AlStatus::of(AlState::PreOp, true));
  EXPECT_EQ(h.fprd16(Harness::station(0), reg::kAlStatusCode),
            al_code(AlStatusCode::InvalidInputConfiguration));
  // Outputs SM in mailbox mode: invalid SyncManager configuration.
  h.write_sm(0, 2, kOutputsStart, 6, 0x64, false);
  h.write_sm(0, 2, kOutputsStart, 6, 0x66);
  h.write_sm(0, 3, kInputsStart, 10, 0x20, false);
  h.write_sm(0, 3, kInputsStart, 10, 0x20);
  EXPECT_EQ(h.request(0, AlState::SafeOp, true), AlStatus::of(AlState::PreOp, true));
  EXPECT_EQ(h.fprd16(Harness::station(0), reg::kAlStatusCode),
            al_code(AlStatusCode::InvalidSyncManagerConfiguration));
  h.write_sm(0, 2, kOutputsStart, 6, 0x64, false);
  h.write_sm(0, 2, kOutputsStart, 6, 0x64);
  EXPECT_EQ(h.request(0, AlState::SafeOp, true), AlStatus::of(AlState::SafeOp));
}

TEST(AlState, OpWaitsForTheFirstOutputsThenTimesOut) {
  SegmentOptions options;
  options.esc.op_outputs_timeout = std::chrono::milliseconds{100};
  Harness h("servo:1", options);
  h.assign_stations();
  h.configure_mailbox(0);
  const auto size = h.configure_process_data(0, 0x10000);
  ASSERT_EQ(h.request(0, AlState::PreOp), AlStatus::of(AlState::PreOp));
  ASSERT_EQ(h.request(0, AlState::SafeOp), AlStatus::of(AlState::SafeOp));
  // OP requested before any outputs: stays SAFEOP without error while it waits.
  EXPECT_EQ(h.request(0, AlState::Op), AlStatus::of(AlState::SafeOp));
  auto lrw = h.run(Harness::make(Command::LRW, 0x10000, Bytes(size, 0)));
  EXPECT_EQ(lrw.wkc, 3);
  EXPECT_EQ(AlStatus::decode(h.fprd16(Harness::station(0), reg::kAlStatus)), AlStatus::of(AlState::Op));

  // Back to SAFEOP, ask for OP, send nothing: after the timeout, 0x001B.
  ASSERT_EQ(h.request(0, AlState::PreOp), AlStatus::of(AlState::PreOp));
  ASSERT_EQ(h.request(0, AlState::SafeOp), AlStatus::of(AlState::SafeOp));
  EXPECT_EQ(h.request(0, AlState::Op), AlStatus::of(AlState::SafeOp));
  h.clock.advance(std::chrono::milliseconds{101});
  EXPECT_EQ(AlStatus::decode(h.fprd16(Harness::station(0), reg::kAlStatus)),
            AlStatus::of(AlState::SafeOp, true));
  EXPECT_EQ(h.fprd16(Harness::station(0), reg::kAlStatusCode), al_code(AlStatusCode::SyncManagerWatchdog));
}

TEST(AlState, ProcessDataIsDeniedBeforeSafeOp) {
  Harness h("servo:1");
  h.assign_stations();
  h.configure_mailbox(0);
  const auto size = h.configure_process_data(0, 0);
  ASSERT_EQ(h.request(0, AlState::PreOp), AlStatus::of(AlState::PreOp));
  EXPECT_EQ(h.run(Harness::make(Command::LRW, 0, Bytes(size, 0))).wkc, 0);
  ASSERT_EQ(h.request(0, AlState::SafeOp), AlStatus::of(AlState::SafeOp));
  EXPECT_EQ(h.run(Harness::make(Command::LRW, 0, Bytes(size, 0))).wkc, 3);
}

// "servo:1,digital-io:1" with process data, both in OP; the process image's size.
std::size_t servo_and_io_in_op(Harness& h) {
  h.assign_stations();
  h.configure_mailbox(0);
  std::size_t size = h.configure_process_data(0, 0);
  size += h.configure_process_data(1, static_cast<std::uint32_t>(size));
  for (std::size_t p = 0; p < 2; ++p) {
    EXPECT_EQ(h.request(p, AlState::PreOp), AlStatus::of(AlState::PreOp)) << p;
    EXPECT_EQ(h.request(p, AlState::SafeOp), AlStatus::of(AlState::SafeOp)) << p;
  }
  h.run(Harness::make(Command::LRW, 0, Bytes(size, 0)));
  for (std::size_t p = 0; p < 2; ++p) {
    EXPECT_EQ(h.request(p, AlState::Op), AlStatus::of(AlState::Op)) << p;
  }
  return size;
}

TEST(AlState, AnEmulationThatDidNotRunDoesNotCountThatTimeAgainstTheMaster) {
  // The segment served by a SegmentRunner (as the plant serves its robots): a runner turn 300 ms
  // after the last one (its process was not scheduled) finds the master's frame waiting; the
  // watchdog (100 ms) keeps counting only the time the emulation ran.
  Harness h("servo:1,digital-io:1");
  const std::size_t size = servo_and_io_in_op(h);
  auto pair = make_memory_link_pair();
  SegmentRunner runner(*h.segment, *pair.b);
  Frame f;
  f.datagrams.push_back(Harness::make(Command::LRW, 0, Bytes(size, 0)));
  const Bytes frame = *encode(f);
  Bytes back(kMaxFrameSize);
  const auto turn = [&](bool with_frame, std::chrono::milliseconds later) {
    if (with_frame) {
      ASSERT_TRUE(pair.a->send(frame).ok());
    }
    h.clock.advance(later);
    ASSERT_TRUE(runner.run_once(std::chrono::milliseconds{0}).ok());
    if (with_frame) {
      ASSERT_EQ(*pair.a->receive(back, std::chrono::milliseconds{100}), frame.size());
    }
  };
  for (int i = 0; i < 20; ++i) {
    turn(true, std::chrono::milliseconds{1});
  }
  turn(true, std::chrono::milliseconds{300});  // the stall
  EXPECT_EQ(h.segment->slave(1).state(), AlState::Op);
  EXPECT_EQ(h.segment->slave(1).watchdog_expirations(), 0U);
  // A master that goes silent while the emulation runs: 100 ms later the watchdog trips.
  for (int i = 0; i < 120; ++i) {
    turn(false, std::chrono::milliseconds{1});
  }
  EXPECT_EQ(h.segment->slave(1).watchdog_expirations(), 1U);
  EXPECT_EQ(h.segment->slave(1).al_status(), AlStatus::of(AlState::SafeOp, true));
}

TEST(AlState, WatchdogTripsWhenOutputsStopInOp) {
  Harness h("servo:1,digital-io:1");
  const std::size_t size = servo_and_io_in_op(h);
  // 100 ms default watchdog: cycles every 50 ms keep it alive.
  Bytes image(size, 0);
  image[16] = 0xA5;  // digital-io outputs follow the servo's 6 output and 10 input bytes
  for (int i = 0; i < 5; ++i) {
    h.clock.advance(std::chrono::milliseconds{50});
    EXPECT_EQ(h.run(Harness::make(Command::LRW, 0, image)).wkc, 6);
  }
  auto* dio = h.segment->device<DigitalIo>(1);
  ASSERT_NE(dio, nullptr);
  EXPECT_EQ(dio->outputs(), 0xA5);
  EXPECT_EQ(h.fprd16(Harness::station(1), reg::kWatchdogStatusProcessData) & 1, 1);
  // Silence for longer than 100 ms.
  h.clock.advance(std::chrono::milliseconds{101});
  h.segment->poll();
  for (std::size_t p = 0; p < 2; ++p) {
    EXPECT_EQ(AlStatus::decode(h.fprd16(Harness::station(p), reg::kAlStatus)),
              AlStatus::of(AlState::SafeOp, true));
    EXPECT_EQ(h.fprd16(Harness::station(p), reg::kAlStatusCode), al_code(AlStatusCode::SyncManagerWatchdog));
    EXPECT_EQ(h.fprd16(Harness::station(p), reg::kWatchdogStatusProcessData) & 1, 0);
    EXPECT_EQ(h.fprd(Harness::station(p), reg::kWatchdogCounterProcessData, 1).data[0], 1);
  }
  EXPECT_EQ(dio->outputs(), 0x00);  // safe value
  // Acknowledge and go back to OP.
  EXPECT_EQ(h.request(1, AlState::SafeOp, true), AlStatus::of(AlState::SafeOp));
  h.run(Harness::make(Command::LRW, 0, image));
  EXPECT_EQ(h.request(1, AlState::Op), AlStatus::of(AlState::Op));
}

TEST(AlState, DeviceIdentificationShowsTheIdInTheStatusCode) {
  SegmentOptions options;
  options.esc.device_id = 0x0BAD;
  Harness h("servo:1", options);
  h.assign_stations();
  h.fpwr_value<std::uint16_t>(Harness::station(0), reg::kAlControl, 0x0021);
  EXPECT_EQ(h.fprd16(Harness::station(0), reg::kAlStatus), 0x0021);
  EXPECT_EQ(h.fprd16(Harness::station(0), reg::kAlStatusCode), 0x0BAD);
  h.fpwr_value<std::uint16_t>(Harness::station(0), reg::kAlControl, 0x0001);
  EXPECT_EQ(h.fprd16(Harness::station(0), reg::kAlStatus), 0x0001);
  EXPECT_EQ(h.fprd16(Harness::station(0), reg::kAlStatusCode), 0);
}

TEST(AlState, StatusChangeRaisesTheAlEventInTheIrqField) {
  Harness h("digital-io:1");
  h.assign_stations();
  // ECAT event mask: AL status event (bit 3).
  h.fpwr_value<std::uint16_t>(Harness::station(0), reg::kEcatEventMask, 0x0008);
  h.fpwr_value<std::uint16_t>(Harness::station(0), reg::kAlControl, 0x0002);
  auto d = h.run(Harness::physical(Command::FPRD, Harness::station(0), reg::kType, Bytes(1)));
  EXPECT_EQ(d.irq & 0x0008, 0x0008);
  h.fprd16(Harness::station(0), reg::kAlStatus);  // reading AL status acknowledges
  d = h.run(Harness::physical(Command::FPRD, Harness::station(0), reg::kType, Bytes(1)));
  EXPECT_EQ(d.irq & 0x0008, 0);
}

}  // namespace
}  // namespace sf::ethercat::slave
