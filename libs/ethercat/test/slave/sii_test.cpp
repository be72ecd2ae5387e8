// The SII EEPROM interface 0x0500–0x050F (ET1100 datasheet II §3.45).
#include <gtest/gtest.h>

#include <set>
#include <string>

#include "sf/ethercat/sii.hpp"
#include "sf/ethercat/slave/devices.hpp"
#include "sf/ethercat/slave/standard_objects.hpp"
#include "slave_test_support.hpp"

namespace sf::ethercat::slave {
namespace {

using testing::Harness;
namespace sc = reg::sii_control;

// Reads `words` words from the EEPROM through the interface like a master:
// address, read command, poll busy, read data.
Bytes read_eeprom(Harness& h, std::uint16_t st, std::uint32_t word, std::size_t chunk, std::size_t bytes) {
  Bytes out;
  while (out.size() < bytes) {
    EXPECT_EQ(h.fpwr_value<std::uint32_t>(st, reg::kSiiAddress, word), 1);
    EXPECT_EQ(h.fpwr_value<std::uint16_t>(st, reg::kSiiControlStatus, sc::kCommandRead), 1);
    int polls = 0;
    while ((h.fprd16(st, reg::kSiiControlStatus) & sc::kBusy) != 0) {
      EXPECT_LT(++polls, 10);
      if (polls >= 10)
        return out;
    }
    auto d = h.fprd(st, reg::kSiiData, chunk).data;
    out.insert(out.end(), d.begin(), d.end());
    word += static_cast<std::uint32_t>(chunk / 2);
  }
  out.resize(bytes);
  return out;
}

TEST(Sii, EightByteReadsReturnTheEncodedImage) {
  Harness h("smart-controller:1");
  h.assign_stations();
  const auto st = Harness::station(0);
  EXPECT_NE(h.fprd16(st, reg::kSiiControlStatus) & sc::kRead8Bytes, 0);
  const Bytes expected = *encode_sii(h.segment->slave(0).device().sii());
  const Bytes got = read_eeprom(h, st, 0, 8, expected.size());
  EXPECT_EQ(got, expected);
  auto info = parse_sii(got);
  ASSERT_TRUE(info.ok()) << info.error().describe();
  EXPECT_EQ(info->identity.product_code, kSmartControllerProductCode);
  EXPECT_EQ(info->identity.vendor_id, kVendorId);
  EXPECT_EQ(info->name(), "Smart controller (8 axes, 32 DI, 32 DO)");
  EXPECT_EQ(info->standard_mailbox.rx_size, kMailboxSize);
  ASSERT_EQ(info->rx_pdos.size(), 9u);
  EXPECT_EQ(info->rx_pdos[0].entries[0].index, 0x6040);
  EXPECT_EQ(info->tx_pdos[1].entries[1].index, 0x6864);  // axis 1 position actual
  EXPECT_TRUE(info->supports_dc());
}

TEST(Sii, EveryDeviceKindHasItsOwnNameAsStringOne) {
  // What a master that takes string 1 as the name (SOEM, KickCAT) shows.
  std::set<std::string> names;
  for (const auto kind : device_kinds()) {
    auto device = make_device(kind);
    ASSERT_TRUE(device.ok()) << kind;
    auto info = parse_sii(*encode_sii((*device)->sii()));
    ASSERT_TRUE(info.ok()) << info.error().describe();
    ASSERT_FALSE(info->strings.empty()) << kind;
    EXPECT_EQ(info->strings[0], info->name()) << kind;
    EXPECT_NE(info->strings[0], info->general->group) << kind;
    names.insert(info->strings[0]);
  }
  EXPECT_EQ(names.size(), device_kinds().size());
}

TEST(Sii, FourByteReadsWhenTheEscSaysSo) {
  SegmentOptions options;
  options.esc.sii_read_8_bytes = false;
  Harness h("digital-io:1", options);
  h.assign_stations();
  const auto st = Harness::station(0);
  EXPECT_EQ(h.fprd16(st, reg::kSiiControlStatus) & sc::kRead8Bytes, 0);
  const Bytes expected = *encode_sii(h.segment->slave(0).device().sii());
  EXPECT_EQ(read_eeprom(h, st, 0, 4, expected.size()), expected);
  auto info = parse_sii(expected);
  ASSERT_TRUE(info.ok());
  EXPECT_FALSE(info->standard_mailbox.present());
  ASSERT_EQ(info->tx_pdos.size(), 1u);
  EXPECT_EQ(info->tx_pdos[0].entries[0].index, 0x6000);
  EXPECT_EQ(info->tx_pdos[0].entries[0].bit_length, 8);
}

TEST(Sii, BusyUntilTimePassesOrTheStatusIsPolled) {
  SegmentOptions options;
  options.esc.sii_busy_time = std::chrono::microseconds{100};
  options.esc.sii_busy_polls = 3;
  Harness h("servo:1", options);
  h.assign_stations();
  const auto st = Harness::station(0);
  h.fpwr_value<std::uint32_t>(st, reg::kSiiAddress, 8);  // vendor ID
  h.fpwr_value<std::uint16_t>(st, reg::kSiiControlStatus, sc::kCommandRead);
  // Busy, and the command bits show the running command.
  auto status = h.fprd16(st, reg::kSiiControlStatus);
  EXPECT_NE(status & sc::kBusy, 0);
  EXPECT_EQ(status & sc::kCommandMask, sc::kCommandRead);
  // Writes while busy are ignored.
  h.fpwr_value<std::uint32_t>(st, reg::kSiiAddress, 0);
  EXPECT_EQ(h.segment->slave(0).read32(reg::kSiiAddress), 8u);
  // Time passes: done, command bits cleared, data present.
  h.clock.advance(std::chrono::microseconds{100});
  status = h.fprd16(st, reg::kSiiControlStatus);
  EXPECT_EQ(status & (sc::kBusy | sc::kCommandMask), 0);
  EXPECT_EQ(load_le<std::uint32_t>(h.fprd(st, reg::kSiiData, 4).data.data()), kVendorId);

  // Without time passing, the fourth status poll sees it done.
  h.fpwr_value<std::uint16_t>(st, reg::kSiiControlStatus, sc::kCommandRead);
  for (int i = 0; i < 3; ++i) {
    EXPECT_NE(h.fprd16(st, reg::kSiiControlStatus) & sc::kBusy, 0) << i;
  }
  EXPECT_EQ(h.fprd16(st, reg::kSiiControlStatus) & sc::kBusy, 0);
}

TEST(Sii, AddressPastTheEndAndInvalidCommandsSetTheAcknowledgeError) {
  Harness h("servo:1");
  h.assign_stations();
  const auto st = Harness::station(0);
  const auto words = static_cast<std::uint32_t>(h.segment->slave(0).eeprom().size() / 2);
  h.fpwr_value<std::uint32_t>(st, reg::kSiiAddress, words);
  h.fpwr_value<std::uint16_t>(st, reg::kSiiControlStatus, sc::kCommandRead);
  auto status = h.fprd16(st, reg::kSiiControlStatus);
  EXPECT_NE(status & sc::kAcknowledgeError, 0);
  EXPECT_EQ(status & sc::kBusy, 0);
  // Command 0 clears the error bits.
  h.fpwr_value<std::uint16_t>(st, reg::kSiiControlStatus, 0);
  EXPECT_EQ(h.fprd16(st, reg::kSiiControlStatus) & sc::kAcknowledgeError, 0);
  // 011 is not a command.
  h.fpwr_value<std::uint16_t>(st, reg::kSiiControlStatus, 0x0300);
  EXPECT_NE(h.fprd16(st, reg::kSiiControlStatus) & sc::kAcknowledgeError, 0);
  // A good read afterwards clears it and works.
  h.fpwr_value<std::uint32_t>(st, reg::kSiiAddress, 0);
  h.fpwr_value<std::uint16_t>(st, reg::kSiiControlStatus, sc::kCommandRead);
  h.clock.advance(std::chrono::milliseconds{1});
  EXPECT_EQ(h.fprd16(st, reg::kSiiControlStatus) & (sc::kAcknowledgeError | sc::kBusy), 0);
}

TEST(Sii, WritesNeedTheWriteEnableBitInTheSameAccess) {
  Harness h("servo:1");
  h.assign_stations();
  const auto st = Harness::station(0);
  const std::uint32_t word = 0x0E;  // serial number, low word
  h.fpwr_value<std::uint32_t>(st, reg::kSiiAddress, word);
  h.fpwr_value<std::uint16_t>(st, reg::kSiiData, 0xBEEF);
  h.fpwr_value<std::uint16_t>(st, reg::kSiiControlStatus, sc::kCommandWrite);
  EXPECT_NE(h.fprd16(st, reg::kSiiControlStatus) & sc::kWriteEnableError, 0);
  EXPECT_NE(load_le<std::uint16_t>(&h.segment->slave(0).eeprom()[2 * word]), 0xBEEF);

  h.fpwr_value<std::uint16_t>(st, reg::kSiiControlStatus, sc::kCommandWrite | sc::kWriteEnable);
  h.clock.advance(std::chrono::milliseconds{1});
  const auto status = h.fprd16(st, reg::kSiiControlStatus);
  EXPECT_EQ(status & (sc::kWriteEnableError | sc::kBusy | sc::kWriteEnable), 0);
  EXPECT_EQ(load_le<std::uint16_t>(&h.segment->slave(0).eeprom()[2 * word]), 0xBEEF);
  EXPECT_EQ(load_le<std::uint16_t>(read_eeprom(h, st, word, 8, 2).data()), 0xBEEF);
}

TEST(Sii, ConfigurationAreaIsLoadedIntoRegistersAtPowerOn) {
  Harness h("digital-io:1");
  h.assign_stations();
  const auto st = Harness::station(0);
  const auto& sii = h.segment->slave(0).device().sii();
  EXPECT_EQ(h.fprd(st, reg::kPdiControl, 1).data[0], sii.pdi_control & 0xFF);
  EXPECT_EQ(h.fprd16(st, reg::kSiiControlStatus) & (sc::kChecksumError | sc::kLoadError), 0);
}

}  // namespace
}  // namespace sf::ethercat::slave
