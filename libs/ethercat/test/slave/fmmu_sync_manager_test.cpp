// FMMU bit mapping and SyncManager buffer semantics (ET1100 datasheet
// section I §7 and §8).
#include <gtest/gtest.h>

#include "sf/ethercat/slave/devices.hpp"
#include "slave_test_support.hpp"

namespace sf::ethercat::slave {
namespace {

using testing::Harness;

Bytes fmmu_bytes(const FmmuConfig& c) {
  const auto e = c.encode();
  return Bytes(e.begin(), e.end());
}

FmmuConfig bit_fmmu(std::uint32_t logical, std::uint8_t start_bit, std::uint8_t stop_bit,
                    std::uint16_t physical, std::uint8_t physical_bit, std::uint8_t type) {
  FmmuConfig c;
  c.logical_start = logical;
  c.length = 1;
  c.logical_start_bit = start_bit;
  c.logical_stop_bit = stop_bit;
  c.physical_start = physical;
  c.physical_start_bit = physical_bit;
  c.type = type;
  c.active = true;
  return c;
}

TEST(Fmmu, BitGranularWriteAndReadLeaveOtherBitsAlone) {
  Harness h("servo:1");
  h.assign_stations();
  const auto st = Harness::station(0);
  h.fpwr(st, 0x0F80, Bytes{0xF0});
  // Logical bits 4..6 of 0x20000 → physical 0x0F80 bits 1..3 (write).
  ASSERT_EQ(h.fpwr(st, reg::fmmu(0), fmmu_bytes(bit_fmmu(0x20000, 4, 6, 0x0F80, 1, kFmmuWrite))), 1);
  auto d = h.run(Harness::make(Command::LWR, 0x20000, Bytes{0x50}));  // bits 4 and 6 set
  EXPECT_EQ(d.wkc, 1);
  EXPECT_EQ(h.segment->slave(0).read8(0x0F80), 0xF0 | 0x02 | 0x08);
  // The same bits read back into logical bits 1..3 of 0x20010; other bits of
  // the datagram are kept.
  ASSERT_EQ(h.fpwr(st, reg::fmmu(1), fmmu_bytes(bit_fmmu(0x20010, 1, 3, 0x0F80, 1, kFmmuRead))), 1);
  d = h.run(Harness::make(Command::LRD, 0x20010, Bytes{0x81}));
  EXPECT_EQ(d.wkc, 1);
  EXPECT_EQ(d.data[0], 0x81 | 0x02 | 0x08);
  // Outside every FMMU: nobody answers.
  EXPECT_EQ(h.run(Harness::make(Command::LRD, 0x30000, Bytes{0})).wkc, 0);
}

TEST(Fmmu, TwoSlavesShareOneLogicalByte) {
  Harness h("servo:2");
  h.assign_stations();
  for (std::size_t p = 0; p < 2; ++p) {
    const auto st = Harness::station(p);
    h.fpwr(st, 0x0F80, Bytes{static_cast<std::uint8_t>(p == 0 ? 0x05 : 0x0A)});
    const auto start = static_cast<std::uint8_t>(4 * p);
    ASSERT_EQ(h.fpwr(st, reg::fmmu(0), fmmu_bytes(bit_fmmu(0x100, start, start + 3, 0x0F80, 0, kFmmuRead))),
              1);
  }
  auto d = h.run(Harness::make(Command::LRD, 0x100, Bytes{0}));
  EXPECT_EQ(d.wkc, 2);
  EXPECT_EQ(d.data[0], 0xA5);
}

TEST(Fmmu, MapsSyncManagerStatusRegisters) {
  Harness h("servo:1");
  h.assign_stations();
  h.configure_mailbox(0);
  ASSERT_EQ(h.request(0, AlState::PreOp), AlStatus::of(AlState::PreOp));
  const auto st = Harness::station(0);
  // SM1 status bit 3 (mailbox full) → logical 0x4000 bit 0, as masters do to
  // poll all mailboxes with one LRD.
  ASSERT_EQ(h.fpwr(st, reg::fmmu(2),
                   fmmu_bytes(bit_fmmu(0x4000, 0, 0, reg::sync_manager(1) + reg::kSmStatus, 3, kFmmuRead))),
            1);
  auto d = h.run(Harness::make(Command::LRD, 0x4000, Bytes{0}));
  EXPECT_EQ(d.wkc, 1);
  EXPECT_EQ(d.data[0], 0);
  // An SDO upload request makes a reply appear in SM1.
  Bytes request = *make_sdo_request(SdoInitiateUploadRequest{0x1000, 0, false}, 1);
  request.resize(kMailboxSize, 0);
  ASSERT_EQ(h.fpwr(st, kMailboxOutStart, request), 1);
  d = h.run(Harness::make(Command::LRD, 0x4000, Bytes{0}));
  EXPECT_EQ(d.data[0], 1);
}

TEST(Fmmu, LogicalReadWriteCountsReadAndWriteParts) {
  Harness h("servo:1");
  h.assign_stations();
  const auto st = Harness::station(0);
  // Write FMMU over 0x2000..0x2003, read FMMU over 0x2100..0x2103, one logical range.
  ASSERT_EQ(h.fpwr(st, reg::fmmu(0), fmmu_bytes(FmmuConfig::bytes(0x1000, 0x2000, 4, kFmmuWrite))), 1);
  ASSERT_EQ(h.fpwr(st, reg::fmmu(1), fmmu_bytes(FmmuConfig::bytes(0x1004, 0x2100, 4, kFmmuRead))), 1);
  h.fpwr_value<std::uint32_t>(st, 0x2100, 0x11223344);
  auto d = h.run(Harness::make(Command::LRW, 0x1000, Bytes{1, 2, 3, 4, 0, 0, 0, 0}));
  EXPECT_EQ(d.wkc, 3);
  EXPECT_EQ(h.segment->slave(0).read32(0x2000), 0x04030201u);
  EXPECT_EQ(load_le<std::uint32_t>(&d.data[4]), 0x11223344u);
  EXPECT_EQ(load_le<std::uint32_t>(&d.data[0]), 0x04030201u);  // the write part is passed on unchanged
  // LRD only uses the read FMMU, LWR only the write FMMU.
  EXPECT_EQ(h.run(Harness::make(Command::LRD, 0x1000, Bytes(4, 0))).wkc, 0);
  EXPECT_EQ(h.run(Harness::make(Command::LWR, 0x1004, Bytes(4, 0))).wkc, 0);
  // A datagram that covers only part of an FMMU maps that part.
  d = h.run(Harness::make(Command::LRD, 0x1006, Bytes(4, 0)));
  EXPECT_EQ(d.wkc, 1);
  EXPECT_EQ(load_le<std::uint16_t>(&d.data[0]), 0x1122);
}

TEST(Fmmu, InactiveFmmuMapsNothing) {
  Harness h("servo:1");
  h.assign_stations();
  auto c = FmmuConfig::bytes(0x1000, 0x2000, 4, kFmmuRead);
  c.active = false;
  ASSERT_EQ(h.fpwr(Harness::station(0), reg::fmmu(0), fmmu_bytes(c)), 1);
  EXPECT_EQ(h.run(Harness::make(Command::LRD, 0x1000, Bytes(4, 0))).wkc, 0);
}

// SyncManagers 4..7 are not used by the servo's firmware: their areas show
// the bare ESC behaviour without a PDI side.
TEST(SyncManager, MailboxWriteFillsOnceAndDeniesFurtherWrites) {
  Harness h("servo:1");
  h.assign_stations();
  const auto st = Harness::station(0);
  ASSERT_EQ(h.write_sm(0, 4, 0x2000, 16, 0x26), 1);
  // A write that does not reach the last byte does not fill the mailbox.
  EXPECT_EQ(h.fpwr(st, 0x2000, Bytes(8, 1)), 1);
  EXPECT_EQ(h.fprd(st, reg::sync_manager(4) + reg::kSmStatus, 1).data[0] & sm::kStatusMailboxFull, 0);
  EXPECT_EQ(h.fpwr(st, 0x2008, Bytes(8, 2)), 1);
  EXPECT_NE(h.fprd(st, reg::sync_manager(4) + reg::kSmStatus, 1).data[0] & sm::kStatusMailboxFull, 0);
  // Full: the next write is denied (WKC 0) and changes nothing.
  EXPECT_EQ(h.fpwr(st, 0x2000, Bytes(16, 9)), 0);
  EXPECT_EQ(h.segment->slave(0).read8(0x2000), 1);
  // The master cannot read its own write mailbox.
  EXPECT_EQ(h.fprd(st, 0x2000, 16).wkc, 0);
}

TEST(SyncManager, ReadMailboxEmptyIsDenied) {
  Harness h("servo:1");
  h.assign_stations();
  ASSERT_EQ(h.write_sm(0, 5, 0x2100, 16, 0x22), 1);
  auto d = h.fprd(Harness::station(0), 0x2100, 16);
  EXPECT_EQ(d.wkc, 0);
  EXPECT_EQ(d.data, Bytes(16, 0));
}

TEST(SyncManager, ConfigurationIsWritableOnlyWhileDisabled) {
  Harness h("servo:1");
  h.assign_stations();
  ASSERT_EQ(h.write_sm(0, 4, 0x2000, 16, 0x26), 1);
  h.write_sm(0, 4, 0x2400, 32, 0x26);  // ignored: SM enabled
  auto sm = h.fprd(Harness::station(0), reg::sync_manager(4), 8).data;
  EXPECT_EQ(load_le<std::uint16_t>(&sm[0]), 0x2000);
  h.write_sm(0, 4, 0x2000, 16, 0x26, false);  // disable
  h.write_sm(0, 4, 0x2400, 32, 0x26);
  sm = h.fprd(Harness::station(0), reg::sync_manager(4), 8).data;
  EXPECT_EQ(load_le<std::uint16_t>(&sm[0]), 0x2400);
  EXPECT_EQ(load_le<std::uint16_t>(&sm[2]), 32);
}

TEST(SyncManager, ThreeBufferWriteRotatesBuffersOnTheLastByte) {
  Harness h("servo:1");
  h.assign_stations();
  const auto st = Harness::station(0);
  ASSERT_EQ(h.write_sm(0, 4, 0x2000, 4, 0x04), 1);  // buffered, ECAT writes
  const Esc& esc = h.segment->slave(0);
  EXPECT_EQ(h.fprd(st, reg::sync_manager(4) + reg::kSmStatus, 1).data[0] & sm::kStatusBufferMask, 0x30);
  EXPECT_EQ(h.fpwr(st, 0x2000, Bytes{1, 1, 1, 1}), 1);
  EXPECT_EQ(esc.read32(0x2000), 0x01010101u);  // buffer 1 at start
  EXPECT_EQ(h.fprd(st, reg::sync_manager(4) + reg::kSmStatus, 1).data[0] & sm::kStatusBufferMask, 0x00);
  // The next write goes to the free buffer (the third: the PDI holds the second).
  EXPECT_EQ(h.fpwr(st, 0x2000, Bytes{2, 2, 2, 2}), 1);
  EXPECT_EQ(esc.read32(0x2008), 0x02020202u);
  EXPECT_EQ(esc.read32(0x2000), 0x01010101u);
  EXPECT_EQ(h.fprd(st, reg::sync_manager(4) + reg::kSmStatus, 1).data[0] & sm::kStatusBufferMask, 0x20);
  // A write without the last byte stays in the open buffer.
  EXPECT_EQ(h.fpwr(st, 0x2000, Bytes{3, 3}), 1);
  EXPECT_EQ(h.fprd(st, reg::sync_manager(4) + reg::kSmStatus, 1).data[0] & sm::kStatusBufferMask, 0x20);
}

TEST(SyncManager, ProcessDataRoundTripThroughThreeBuffers) {
  Harness h("digital-io:1,servo:1");
  h.assign_stations();
  h.configure_mailbox(1);
  const std::size_t io = h.configure_process_data(0, 0);
  const std::size_t size = io + h.configure_process_data(1, static_cast<std::uint32_t>(io));
  EXPECT_EQ(size, 2u + 16u);
  for (std::size_t p = 0; p < 2; ++p) {
    ASSERT_EQ(h.request(p, AlState::PreOp), AlStatus::of(AlState::PreOp));
    ASSERT_EQ(h.request(p, AlState::SafeOp), AlStatus::of(AlState::SafeOp));
  }
  auto* dio = h.segment->device<DigitalIo>(0);
  dio->set_inputs(0x3C);
  auto d = h.run(Harness::make(Command::LRW, 0, Bytes(size, 0)));
  EXPECT_EQ(d.wkc, 2 * 3);  // SAFEOP: outputs are taken into the buffers (but not applied)
  EXPECT_EQ(d.data[1], 0x3C);
  // Servo inputs: statusword (switch on disabled) right after its outputs.
  EXPECT_EQ(load_le<std::uint16_t>(&d.data[2 + 6]) & 0x4F, 0x40);
}

}  // namespace
}  // namespace sf::ethercat::slave
