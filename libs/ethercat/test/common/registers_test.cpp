// ESC register map spot checks (ET1100 datasheet II) and the register value types.
#include "sf/ethercat/registers.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

namespace sf::ethercat {
namespace {

using ::testing::HasSubstr;

TEST(RegisterMap, AddressesFromTheDatasheet) {
  EXPECT_EQ(reg::kFmmuCount, 0x0004);
  EXPECT_EQ(reg::kStationAddress, 0x0010);
  EXPECT_EQ(reg::kAlStatusCode, 0x0134);
  EXPECT_EQ(reg::kSiiControlStatus, 0x0502);
  EXPECT_EQ(reg::fmmu(0), 0x0600);
  EXPECT_EQ(reg::fmmu(2), 0x0620);
  EXPECT_EQ(reg::fmmu(15), 0x06F0);
  EXPECT_EQ(reg::sync_manager(0), 0x0800);
  EXPECT_EQ(reg::sync_manager(3), 0x0818);
  EXPECT_EQ(reg::sync_manager(15), 0x0878);
  EXPECT_EQ(reg::dc_receive_time(3), 0x090C);
  EXPECT_EQ(reg::kDcSystemTime, 0x0910);
  EXPECT_EQ(reg::kDcSpeedCounterFilterDepth, 0x0935);
  EXPECT_EQ(reg::kDcStartTimeCyclic, 0x0990);
  EXPECT_EQ(reg::kDcSync1CycleTime, 0x09A4);
  EXPECT_EQ(reg::rx_error_counter(1), 0x0302);
  EXPECT_EQ(reg::lost_link_counter(3), 0x0313);
}

TEST(PortDescriptor, TwoBitsPerPort) {
  // Ports 0,1 EBUS; port 2 MII; port 3 not implemented: 0b00'11'10'10.
  const std::uint8_t d = 0b00111010;
  EXPECT_EQ(port_kind(d, 0), PortKind::ebus);
  EXPECT_EQ(port_kind(d, 1), PortKind::ebus);
  EXPECT_EQ(port_kind(d, 2), PortKind::mii);
  EXPECT_EQ(port_kind(d, 3), PortKind::not_implemented);
}

TEST(AlState, NamesAndBits) {
  EXPECT_EQ(to_string(AlState::Init), "INIT");
  EXPECT_EQ(to_string(AlState::PreOp), "PREOP");
  EXPECT_EQ(to_string(AlState::Bootstrap), "BOOT");
  EXPECT_EQ(to_string(AlState::SafeOp), "SAFEOP");
  EXPECT_EQ(to_string(AlState::Op), "OP");
  EXPECT_EQ(al_state_from_string("safe-op"), AlState::SafeOp);
  EXPECT_EQ(al_state_from_string("Pre-Op"), AlState::PreOp);
  EXPECT_EQ(al_state_from_string("op"), AlState::Op);
  EXPECT_EQ(al_state_from_string("RUN"), std::nullopt);
  EXPECT_EQ(al_state_from_bits(0x0014), AlState::SafeOp);  // error flag ignored
  EXPECT_EQ(al_state_from_bits(0x0008), AlState::Op);
  EXPECT_EQ(al_state_from_bits(0x0005), std::nullopt);
  EXPECT_EQ(al_state_from_bits(0x0000), std::nullopt);
  EXPECT_EQ(kAlStateErrorFlag, 0x10);
}

// One order for master and slave: INIT < PREOP = BOOT < SAFEOP < OP (ETG.1000.6 §6.4.1).
TEST(AlState, RankOrdersTheStatesWithBootBesidePreOp) {
  static_assert(rank(AlState::Init) < rank(AlState::PreOp));
  static_assert(rank(AlState::PreOp) < rank(AlState::SafeOp));
  static_assert(rank(AlState::SafeOp) < rank(AlState::Op));
  EXPECT_EQ(rank(AlState::Bootstrap), rank(AlState::PreOp));
}

TEST(AlStatus, EncodesStateErrorAndIdBits) {
  const AlStatus s = AlStatus::of(AlState::SafeOp, true);
  EXPECT_EQ(s.encode(), 0x0014);
  EXPECT_EQ(AlStatus::decode(0x0014), s);
  EXPECT_EQ(s.to_string(), "SAFEOP + ERROR");
  const AlStatus weird = AlStatus::decode(0x0027);
  EXPECT_EQ(weird.state(), std::nullopt);
  EXPECT_TRUE(weird.id_loaded);
  EXPECT_THAT(weird.to_string(), HasSubstr("invalid"));
  EXPECT_EQ(weird.encode(), 0x0027);
}

TEST(AlControl, EncodesRequestAndAcknowledge) {
  EXPECT_EQ(AlControl::of(AlState::Op).encode(), 0x0008);
  EXPECT_EQ(AlControl::of(AlState::Init, true).encode(), 0x0011);
  const AlControl c = AlControl::decode(0x0032);
  EXPECT_EQ(c.state(), AlState::PreOp);
  EXPECT_TRUE(c.acknowledge);
  EXPECT_TRUE(c.request_id);
}

TEST(DlStatus, PortBits) {
  DlStatus s;
  s.set(DlStatus::kPdiOperational, true);
  s.set_port_open(0);
  s.set_port_closed(1);
  // Datasheet II §3.3: link bits 4..7, loop bits 8/10/12/14, communication bits 9/11/13/15.
  EXPECT_EQ(s.value, 0x0001U | 0x0010U | 0x0200U | 0x0400U);
  EXPECT_TRUE(s.pdi_operational());
  EXPECT_TRUE(s.link(0));
  EXPECT_TRUE(s.communication(0));
  EXPECT_FALSE(s.loop_closed(0));
  EXPECT_FALSE(s.link(1));
  EXPECT_TRUE(s.loop_closed(1));
  s.set_link(3, true);
  EXPECT_EQ(s.value & 0x0080U, 0x0080U);
  s.set_link(3, false);
  EXPECT_FALSE(s.link(3));
}

TEST(Fmmu, EncodesTheSixteenByteLayout) {
  FmmuConfig f;
  f.logical_start = 0x00010203;
  f.length = 0x0405;
  f.logical_start_bit = 2;
  f.logical_stop_bit = 5;
  f.physical_start = 0x1100;
  f.physical_start_bit = 1;
  f.type = kFmmuRead | kFmmuWrite;
  f.active = true;
  const std::array<std::uint8_t, 16> expected{0x03, 0x02, 0x01, 0x00, 0x05, 0x04, 0x02, 0x05,
                                              0x00, 0x11, 0x01, 0x03, 0x01, 0x00, 0x00, 0x00};
  EXPECT_EQ(f.encode(), expected);
  auto back = FmmuConfig::decode(expected);
  ASSERT_TRUE(back);
  EXPECT_EQ(*back, f);
  EXPECT_TRUE(back->reads());
  EXPECT_TRUE(back->writes());
}

TEST(Fmmu, ByteMappingHelperAndMalformedInput) {
  const FmmuConfig f = FmmuConfig::bytes(0x100, 0x1800, 4, kFmmuWrite);
  EXPECT_EQ(f.logical_start_bit, 0);
  EXPECT_EQ(f.logical_stop_bit, 7);
  EXPECT_TRUE(f.active);
  EXPECT_FALSE(f.reads());
  auto rt = FmmuConfig::decode(f.encode());
  ASSERT_TRUE(rt);
  EXPECT_EQ(*rt, f);

  EXPECT_FALSE(FmmuConfig::decode(ByteSpan(f.encode()).first(15)));
  auto bad = f.encode();
  bad[7] = 8;  // stop bit 8 does not exist
  auto r = FmmuConfig::decode(bad);
  ASSERT_FALSE(r);
  EXPECT_THAT(r.error().message, HasSubstr("bit number"));
}

TEST(SyncManager, EncodesTheEightByteLayout) {
  const auto mbx_out =
      SyncManagerConfig::make(0x1000, 128, SyncManagerMode::mailbox, SyncManagerDirection::write);
  // Control 0x26: mailbox (10), write (01), PDI interrupt (bit 5) — the usual SM0.
  EXPECT_EQ(mbx_out.control, 0x26);
  EXPECT_EQ(mbx_out.encode(), (std::array<std::uint8_t, 8>{0x00, 0x10, 0x80, 0x00, 0x26, 0x00, 0x01, 0x00}));
  const auto mbx_in =
      SyncManagerConfig::make(0x1080, 128, SyncManagerMode::mailbox, SyncManagerDirection::read);
  EXPECT_EQ(mbx_in.control, 0x22);
  const auto outputs =
      SyncManagerConfig::make(0x1100, 4, SyncManagerMode::buffered, SyncManagerDirection::write);
  EXPECT_EQ(outputs.control, 0x04);
  const auto inputs =
      SyncManagerConfig::make(0x1180, 4, SyncManagerMode::buffered, SyncManagerDirection::read, false);
  EXPECT_EQ(inputs.control, 0x00);
  EXPECT_FALSE(inputs.enabled());

  for (const auto& sm : {mbx_out, mbx_in, outputs, inputs}) {
    auto back = SyncManagerConfig::decode(sm.encode());
    ASSERT_TRUE(back);
    EXPECT_EQ(*back, sm);
  }
  EXPECT_EQ(mbx_out.mode(), SyncManagerMode::mailbox);
  EXPECT_EQ(mbx_out.direction(), SyncManagerDirection::write);
  EXPECT_EQ(inputs.mode(), SyncManagerMode::buffered);
  EXPECT_EQ(inputs.direction(), SyncManagerDirection::read);
  EXPECT_TRUE(mbx_out.contains(0x1000));
  EXPECT_TRUE(mbx_out.contains(0x107F));
  EXPECT_FALSE(mbx_out.contains(0x1080));
  EXPECT_FALSE(mbx_out.contains(0x0FFF));
}

TEST(SyncManager, StatusAndActivateBitsAndShortInput) {
  const std::array<std::uint8_t, 8> raw{0x00, 0x10, 0x80, 0x00, 0x26, 0x08, 0x03, 0x01};
  auto sm = SyncManagerConfig::decode(raw);
  ASSERT_TRUE(sm);
  EXPECT_TRUE(sm->mailbox_full());
  EXPECT_TRUE(sm->enabled());
  EXPECT_TRUE(sm->repeat());
  EXPECT_EQ(sm->pdi_control, 0x01);
  EXPECT_TRUE(sm->mode_valid());
  auto reserved_mode = *sm;
  reserved_mode.control = 0x01;
  EXPECT_FALSE(reserved_mode.mode_valid());
  auto short_input = SyncManagerConfig::decode(ByteSpan(raw).first(7));
  ASSERT_FALSE(short_input);
  EXPECT_EQ(short_input.error().code, Errc::malformed);
}

}  // namespace
}  // namespace sf::ethercat
