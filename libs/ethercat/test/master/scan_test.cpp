// Scan and SII against the emulated segment.
#include <gtest/gtest.h>

#include "segment_bench.hpp"
#include "sf/ethercat/slave/devices.hpp"
#include "sf/ethercat/slave/standard_objects.hpp"

namespace sf::ethercat::master::test {
namespace {

TEST(Scan, CountsAddressesAndIdentifiesSlaves) {
  Bench b("smart-controller:1,digital-io:2,servo:1");
  auto n = b.master->scan();
  ASSERT_TRUE(n.ok()) << n.error().describe();
  ASSERT_EQ(*n, 4U);
  const auto& slaves = b.master->slaves();
  for (std::size_t p = 0; p < slaves.size(); ++p) {
    EXPECT_EQ(slaves[p].station, 0x1001 + p);
    // The ESC itself holds the address the master wrote.
    EXPECT_EQ(b.segment->slave(p).station_address(), 0x1001 + p);
    EXPECT_EQ(slaves[p].esc.type, 0x11);
    EXPECT_TRUE(slaves[p].esc.dc_supported());
    EXPECT_EQ(slaves[p].esc.fmmus, 8);
    EXPECT_EQ(slaves[p].sii.identity.vendor_id, slave::kVendorId);
    EXPECT_EQ(slaves[p].al_status.state(), AlState::Init);
  }
  EXPECT_EQ(slaves[0].sii.identity.product_code, slave::kSmartControllerProductCode);
  EXPECT_EQ(slaves[1].sii.identity.product_code, slave::kDigitalIoProductCode);
  EXPECT_EQ(slaves[3].sii.identity.product_code, slave::kServoProductCode);
  // Mailbox: the CoE devices have one, the digital IO none.
  EXPECT_TRUE(slaves[0].mailbox.coe());
  EXPECT_EQ(slaves[0].mailbox.rx_offset, slave::kMailboxOutStart);
  EXPECT_EQ(slaves[0].mailbox.tx_size, slave::kMailboxSize);
  EXPECT_FALSE(slaves[1].mailbox.present());
  // DL status: every port 1 leads on except the last slave's.
  EXPECT_TRUE(slaves[0].port_open(1));
  EXPECT_FALSE(slaves[3].port_open(1));
  EXPECT_FALSE(slaves[0].name().empty());
}

TEST(Scan, SiiImageIsTheSlavesEeprom) {
  Bench b("servo:1");
  ASSERT_TRUE(b.master->scan().ok());
  auto image = b.master->read_sii_image(0);
  ASSERT_TRUE(image.ok()) << image.error().describe();
  const auto eeprom = b.segment->slave(0).eeprom();
  ASSERT_LE(image->size(), eeprom.size());
  EXPECT_TRUE(std::equal(image->begin(), image->end(), eeprom.begin()));
  // And parse_sii() of it is what the device put there.
  EXPECT_EQ(b.master->slave_info(0).sii.identity, b.segment->slave(0).device().sii().identity);
  EXPECT_EQ(b.master->slave_info(0).sii.tx_pdos.size(), b.segment->slave(0).device().sii().tx_pdos.size());
}

TEST(Scan, FourByteSiiReadsWork) {
  slave::SegmentOptions so;
  so.esc.sii_read_8_bytes = false;
  Bench b("digital-io:1", quick_options(), so);
  ASSERT_TRUE(b.master->scan().ok());
  auto words = b.master->read_sii(0, sii::kVendorId, 3);  // odd number of words
  ASSERT_TRUE(words.ok()) << words.error().describe();
  ASSERT_EQ(words->size(), 6U);
  EXPECT_EQ(load_le<std::uint32_t>(words->data()), slave::kVendorId);
}

TEST(Scan, EmptySegmentFindsNothing) {
  Bench b("servo:1");
  b.segment->disconnect(0);
  auto n = b.master->scan();
  // Nobody answers: every frame is lost, which the master reports.
  if (n.ok()) {
    EXPECT_EQ(*n, 0U);
  } else {
    EXPECT_EQ(n.error().code, Errc::timeout);
  }
  EXPECT_FALSE(b.master->bring_up().ok());
}

TEST(Scan, BadPositionIsAnError) {
  Bench b("servo:1");
  ASSERT_TRUE(b.master->scan().ok());
  EXPECT_FALSE(b.master->read_sii(5, 0, 4).ok());
  EXPECT_FALSE(b.master->sdo_upload(5, 0x1000, 0).ok());
  EXPECT_FALSE(b.master->request_state(5, AlState::PreOp).ok());
}

}  // namespace
}  // namespace sf::ethercat::master::test
