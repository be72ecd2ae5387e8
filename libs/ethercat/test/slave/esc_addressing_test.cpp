// Addressing, the commands and their working counters, register access
// rules (ET1100 datasheet II, ETG.1000.4 §5.4).
#include <gtest/gtest.h>

#include "sf/ethercat/slave/devices.hpp"
#include "slave_test_support.hpp"

namespace sf::ethercat::slave {
namespace {

using testing::Harness;

TEST(EscAddressing, BroadcastReadCountsEverySlaveAndIncrementsPosition) {
  Harness h("servo:2,digital-io:3");
  auto d = h.run(Harness::physical(Command::BRD, 0, reg::kType, Bytes(1, 0)));
  EXPECT_EQ(d.wkc, 5);
  EXPECT_EQ(d.data[0], 0x11);  // ET1100
  EXPECT_EQ(d.adp(), 5);
}

TEST(EscAddressing, BroadcastReadOrsTheDataOfAllSlaves) {
  Harness h("servo:1,digital-io:1");
  // Station addresses 0x0100 and 0x0002: BRD of 0x0010 returns their OR.
  h.run(Harness::physical(Command::APWR, 0, reg::kStationAddress, Harness::le<std::uint16_t>(0x0100)));
  h.run(Harness::physical(Command::APWR, 0xFFFF, reg::kStationAddress, Harness::le<std::uint16_t>(0x0002)));
  auto d = h.run(Harness::physical(Command::BRD, 0, reg::kStationAddress, Bytes(2, 0)));
  EXPECT_EQ(load_le<std::uint16_t>(d.data.data()), 0x0102);
  EXPECT_EQ(d.wkc, 2);
}

TEST(EscAddressing, AutoIncrementAddressesThePositionThatSeesZero) {
  Harness h("servo:3");
  auto w = h.run(Harness::physical(Command::APWR, static_cast<std::uint16_t>(-2), reg::kStationAddress,
                                   Harness::le<std::uint16_t>(0x0BEE)));
  EXPECT_EQ(w.wkc, 1);
  EXPECT_EQ(w.adp(), 1);  // incremented by all three
  EXPECT_EQ(h.segment->slave(2).station_address(), 0x0BEE);
  EXPECT_EQ(h.segment->slave(0).station_address(), 0);
  auto r =
      h.run(Harness::physical(Command::APRD, static_cast<std::uint16_t>(-2), reg::kStationAddress, Bytes(2)));
  EXPECT_EQ(r.wkc, 1);
  EXPECT_EQ(load_le<std::uint16_t>(r.data.data()), 0x0BEE);
  // A position past the end: nobody answers.
  EXPECT_EQ(h.run(Harness::physical(Command::APRD, static_cast<std::uint16_t>(-3), 0, Bytes(2))).wkc, 0);
}

TEST(EscAddressing, ConfiguredAddressAndAliasWhenEnabled) {
  SegmentOptions options;
  options.device.station_alias = 0x0042;
  Harness h("servo:1,servo:1", options);
  h.assign_stations();
  EXPECT_EQ(h.fprd16(Harness::station(1), reg::kStationAddress), Harness::station(1));
  // The alias comes from SII word 4 and is read-only for the master.
  EXPECT_EQ(h.fprd16(Harness::station(0), reg::kStationAlias), 0x0042);
  EXPECT_EQ(h.fpwr_value<std::uint16_t>(Harness::station(0), reg::kStationAlias, 0x0099), 1);
  EXPECT_EQ(h.fprd16(Harness::station(0), reg::kStationAlias), 0x0042);
  // Alias addressing only after DL control bit 24 is set.
  EXPECT_EQ(h.fprd(0x0042, reg::kType, 1).wkc, 0);
  EXPECT_EQ(h.fpwr(Harness::station(1), reg::kDlControl + 3, Bytes{0x01}), 1);
  EXPECT_EQ(h.fprd(0x0042, reg::kType, 1).wkc, 1);
}

TEST(EscAddressing, ReadWriteCommandsCountOneForReadTwoForWrite) {
  Harness h("servo:2");
  h.assign_stations();
  // FPRW: old value back, new value stored, WKC 3.
  auto d = h.run(
      Harness::physical(Command::FPRW, Harness::station(0), 0x0F80, Harness::le<std::uint32_t>(0xCAFE)));
  EXPECT_EQ(d.wkc, 3);
  EXPECT_EQ(load_le<std::uint32_t>(d.data.data()), 0u);
  EXPECT_EQ(h.segment->slave(0).read32(0x0F80), 0xCAFEu);
  // APRW the same way.
  auto a = h.run(Harness::physical(Command::APRW, static_cast<std::uint16_t>(-1), 0x0F80,
                                   Harness::le<std::uint32_t>(7)));
  EXPECT_EQ(a.wkc, 3);
  EXPECT_EQ(h.segment->slave(1).read32(0x0F80), 7u);
  // BRW: every slave writes, the data comes back ORed with the old contents.
  auto b = h.run(Harness::physical(Command::BRW, 0, 0x0F80, Harness::le<std::uint32_t>(0x100)));
  EXPECT_EQ(b.wkc, 6);
  EXPECT_EQ(load_le<std::uint32_t>(b.data.data()), 0x100u | 0xCAFEu | 7u);
  EXPECT_EQ(h.segment->slave(0).read32(0x0F80), 0x100u);
}

TEST(EscAddressing, ReadMultipleWriteReadsAtTheAddressedSlaveAndWritesElsewhere) {
  Harness h("servo:3");
  h.assign_stations();
  h.fpwr_value<std::uint32_t>(Harness::station(1), 0x0F80, 0x11111111);
  // FRMW: the addressed slave (station 2) reads, slaves before it get the
  // master's data, slaves after it the data it read.
  auto f = h.run(
      Harness::physical(Command::FRMW, Harness::station(1), 0x0F80, Harness::le<std::uint32_t>(0xAAAA)));
  EXPECT_EQ(f.wkc, 3);
  EXPECT_EQ(load_le<std::uint32_t>(f.data.data()), 0x11111111u);
  EXPECT_EQ(h.segment->slave(0).read32(0x0F80), 0xAAAAu);
  EXPECT_EQ(h.segment->slave(2).read32(0x0F80), 0x11111111u);
  // ARMW: the same by position; the first slave (position 0) is the usual reference.
  h.fpwr_value<std::uint32_t>(Harness::station(0), 0x0F80, 0x22222222);
  auto a = h.run(Harness::physical(Command::ARMW, 0, 0x0F80, Harness::le<std::uint32_t>(0)));
  EXPECT_EQ(a.wkc, 3);
  EXPECT_EQ(h.segment->slave(1).read32(0x0F80), 0x22222222u);
  EXPECT_EQ(h.segment->slave(2).read32(0x0F80), 0x22222222u);
}

TEST(EscAddressing, BroadcastWriteReachesEverySlave) {
  Harness h("servo:2,digital-io:2");
  auto d = h.run(Harness::physical(Command::BWR, 0, 0x0F80, Harness::le<std::uint16_t>(0x5A5A)));
  EXPECT_EQ(d.wkc, 4);
  for (std::size_t p = 0; p < 4; ++p) {
    EXPECT_EQ(h.segment->slave(p).read16(0x0F80), 0x5A5A) << p;
  }
}

TEST(EscAddressing, PhysicalReadWriteOffsetSeparatesTheWriteAddress) {
  Harness h("servo:1");
  h.assign_stations();
  ASSERT_EQ(h.fpwr_value<std::uint16_t>(Harness::station(0), reg::kPhysicalRwOffset, 0x10), 1);
  auto d = h.run(
      Harness::physical(Command::FPRW, Harness::station(0), 0x0F80, Harness::le<std::uint16_t>(0xABCD)));
  EXPECT_EQ(d.wkc, 3);
  EXPECT_EQ(h.segment->slave(0).read16(0x0F80), 0);
  EXPECT_EQ(h.segment->slave(0).read16(0x0F90), 0xABCD);
}

TEST(EscAddressing, ReadOnlyRegistersIgnoreWritesButCountTheWorkingCounter) {
  Harness h("servo:1");
  h.assign_stations();
  EXPECT_EQ(h.fpwr(Harness::station(0), reg::kType, Bytes{0x55}), 1);
  EXPECT_EQ(h.fprd(Harness::station(0), reg::kType, 1).data[0], 0x11);
  EXPECT_EQ(h.fpwr_value<std::uint16_t>(Harness::station(0), reg::kAlStatus, 0x0008), 1);
  EXPECT_EQ(h.fprd16(Harness::station(0), reg::kAlStatus), 0x0001);
  // SM status (+5) and PDI control (+7) are read-only, the rest of SM0 is not.
  EXPECT_EQ(
      h.fpwr(Harness::station(0), reg::sync_manager(0), Bytes{0x00, 0x10, 0x80, 0, 0x26, 0xFF, 0x00, 0xFF}),
      1);
  auto sm = h.fprd(Harness::station(0), reg::sync_manager(0), 8).data;
  EXPECT_EQ(sm[1], 0x10);
  EXPECT_EQ(sm[4], 0x26);
  EXPECT_EQ(sm[5], 0x00);
}

TEST(EscAddressing, RegisterWriteProtectionNeedsEnableInTheSameFrame) {
  Harness h("servo:1");
  h.assign_stations();
  const auto st = Harness::station(0);
  ASSERT_EQ(h.fpwr(st, reg::kRegisterWriteProtection, Bytes{0x01}), 1);
  // Protected: a register write alone is discarded; user RAM is not protected.
  h.fpwr_value<std::uint16_t>(st, reg::kWatchdogTimeProcessData, 77);
  EXPECT_EQ(h.fprd16(st, reg::kWatchdogTimeProcessData), reg::kDefaultWatchdogTime);
  h.fpwr_value<std::uint16_t>(st, 0x0F80, 0x1234);
  EXPECT_EQ(h.fprd16(st, 0x0F80), 0x1234);
  // With the enable bit written first in the same frame it goes through.
  h.run(
      {Harness::physical(Command::FPWR, st, reg::kRegisterWriteEnable, Bytes{0x01}),
       Harness::physical(Command::FPWR, st, reg::kWatchdogTimeProcessData, Harness::le<std::uint16_t>(77))});
  EXPECT_EQ(h.fprd16(st, reg::kWatchdogTimeProcessData), 77);
  // The enable does not outlive its frame.
  h.fpwr_value<std::uint16_t>(st, reg::kWatchdogTimeProcessData, 88);
  EXPECT_EQ(h.fprd16(st, reg::kWatchdogTimeProcessData), 77);
}

TEST(EscAddressing, EscWriteProtectionCoversProcessRamToo) {
  Harness h("servo:1");
  h.assign_stations();
  const auto st = Harness::station(0);
  ASSERT_EQ(h.fpwr(st, reg::kEscWriteProtection, Bytes{0x01}), 1);
  h.fpwr_value<std::uint32_t>(st, 0x2000, 0xAABBCCDD);
  EXPECT_EQ(h.segment->slave(0).read32(0x2000), 0u);
  h.run({Harness::physical(Command::FPWR, st, reg::kEscWriteEnable, Bytes{0x01}),
         Harness::physical(Command::FPWR, st, 0x2000, Harness::le<std::uint32_t>(0xAABBCCDD))});
  EXPECT_EQ(h.segment->slave(0).read32(0x2000), 0xAABBCCDDu);
}

TEST(EscAddressing, ProcessRamEndsAtItsSizeAndReadsZeroBeyond) {
  Harness h("servo:1");
  h.assign_stations();
  const auto st = Harness::station(0);
  EXPECT_EQ(h.fpwr_value<std::uint32_t>(st, 0x2FFC, 0x01020304), 1);  // last word of 8 KiB
  EXPECT_EQ(h.segment->slave(0).read32(0x2FFC), 0x01020304u);
  EXPECT_EQ(h.fpwr_value<std::uint32_t>(st, 0x3000, 0x01020304), 1);
  EXPECT_EQ(h.fprd(st, 0x3000, 4).data, (Bytes{0, 0, 0, 0}));
}

TEST(EscAddressing, NopAndReservedCommandsAreForwardedUntouched) {
  Harness h("servo:2");
  auto nop = h.run(Harness::physical(Command::NOP, 0, 0, Bytes{1, 2, 3}));
  EXPECT_EQ(nop.wkc, 0);
  EXPECT_EQ(nop.adp(), 0);
  EXPECT_EQ(nop.data, (Bytes{1, 2, 3}));
}

TEST(EscAddressing, ReturnedFrameHasLocallyAdministeredSourceMac) {
  Harness h("digital-io:1");
  h.run(Harness::physical(Command::BRD, 0, 0, Bytes(2)));
  EXPECT_EQ(h.last_frame[6], 0x02);  // 0x00 | 0x02
  EXPECT_EQ(h.last_frame[7], 0x11);
}

TEST(EscAddressing, DlStatusShowsOpenPortsAndTheClosedLoopOfTheLastSlave) {
  Harness h("servo:3");
  h.assign_stations();
  const DlStatus first{h.fprd16(Harness::station(0), reg::kDlStatus)};
  EXPECT_TRUE(first.pdi_operational());
  EXPECT_TRUE(first.link(0));
  EXPECT_TRUE(first.link(1));
  EXPECT_FALSE(first.loop_closed(0));
  EXPECT_FALSE(first.loop_closed(1));
  EXPECT_TRUE(first.communication(1));
  const DlStatus last{h.fprd16(Harness::station(2), reg::kDlStatus)};
  EXPECT_TRUE(last.link(0));
  EXPECT_FALSE(last.link(1));
  EXPECT_TRUE(last.loop_closed(1));
  EXPECT_TRUE(last.loop_closed(2));
}

TEST(EscAddressing, ClosingPort1ByDlControlHidesTheSlavesBehind) {
  Harness h("servo:3");
  h.assign_stations();
  // Loop port 1 (DL control bits 11:10) = 11: always closed.
  ASSERT_EQ(h.fpwr(Harness::station(0), reg::kDlControl + 1, Bytes{0x0C}), 1);
  EXPECT_EQ(h.run(Harness::physical(Command::BRD, 0, reg::kType, Bytes(1))).wkc, 1);
  ASSERT_EQ(h.fpwr(Harness::station(0), reg::kDlControl + 1, Bytes{0x00}), 1);
  EXPECT_EQ(h.run(Harness::physical(Command::BRD, 0, reg::kType, Bytes(1))).wkc, 3);
}

TEST(EscAddressing, EscResetSequenceRestoresPowerOnDefaults) {
  Harness h("servo:1");
  h.assign_stations();
  for (std::uint8_t c : {std::uint8_t{0x52}, std::uint8_t{0x45}, std::uint8_t{0x53}}) {
    h.run(Harness::physical(Command::APWR, 0, reg::kEscResetEcat, Bytes{c}));
  }
  EXPECT_EQ(h.segment->slave(0).station_address(), 0);
  // A broken sequence does nothing.
  h.assign_stations();
  for (std::uint8_t c : {std::uint8_t{0x52}, std::uint8_t{0x00}, std::uint8_t{0x53}}) {
    h.run(Harness::physical(Command::APWR, 0, reg::kEscResetEcat, Bytes{c}));
  }
  EXPECT_EQ(h.segment->slave(0).station_address(), Harness::station(0));
}

TEST(EscAddressing, MalformedFramesAreCountedAndNotProcessed) {
  Harness h("servo:1");
  Frame f;
  f.datagrams.push_back(
      Harness::physical(Command::APWR, 0, reg::kStationAddress, Harness::le<std::uint16_t>(5)));
  Bytes bytes = *encode(f);
  // Claim a longer datagram than the frame holds.
  store_le<std::uint16_t>(&bytes[kEthernetHeaderSize + kEcatHeaderSize + 6], 0x07F0);
  EXPECT_FALSE(h.segment->process(bytes));
  EXPECT_EQ(h.segment->counters().malformed, 1u);
  EXPECT_EQ(h.segment->slave(0).station_address(), 0);
  // Too short to hold even the headers.
  Bytes tiny(10, 0);
  EXPECT_FALSE(h.segment->process(tiny));
  // Not EtherCAT.
  bytes = *encode(f);
  bytes[12] = 0x08;
  bytes[13] = 0x00;
  EXPECT_FALSE(h.segment->process(bytes));
  EXPECT_EQ(h.segment->counters().malformed, 3u);
}

}  // namespace
}  // namespace sf::ethercat::slave
