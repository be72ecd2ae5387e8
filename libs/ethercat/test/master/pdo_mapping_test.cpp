// PDO mapping from CoE (0x1C12/0x1C13 → 0x16xx/0x1Axx) and from the SII
// categories, and a remapped slave running with its new process image.
#include <array>

#include <gtest/gtest.h>

#include "segment_bench.hpp"
#include "sf/ethercat/sdo_abort_codes.hpp"
#include "sf/ethercat/slave/devices.hpp"
#include "sf/ethercat/slave/standard_objects.hpp"

namespace sf::ethercat::master::test {
namespace {

// A CoE slave with a fixed mapping: no 0x1C12/0x1C13 in its dictionary (an
// upload answers "object does not exist"), the PDOs only in its SII.
class FixedMappingServo final : public slave::Device {
 public:
  FixedMappingServo() {
    slave::add_identity_objects(od_, slave::DeviceIdentity{0x00020192, slave::kVendorId, 0x00029999,
                                                           0x00010000, 1, "Fixed-mapping servo"});
  }
  [[nodiscard]] std::string_view kind() const override { return "fixed-servo"; }
  [[nodiscard]] const SiiInfo& sii() const override { return servo_.sii(); }
  [[nodiscard]] slave::ObjectDictionary& objects() override { return od_; }
  [[nodiscard]] bool outputs_safe() const override { return true; }

 private:
  slave::Servo servo_;
  slave::ObjectDictionary od_;
};

TEST(PdoMapping, FromCoeForAMailboxSlave) {
  Bench b("servo:1");
  ASSERT_TRUE(b.master->scan().ok());
  ASSERT_TRUE(b.master->request_state(AlState::PreOp).ok());
  auto m = b.master->read_pdo_mapping(0);
  ASSERT_TRUE(m.ok()) << m.error().describe();
  EXPECT_EQ(m->source, PdoMapping::Source::coe);
  ASSERT_EQ(m->outputs.size(), 1U);
  EXPECT_EQ(m->outputs[0].index, 0x1600);
  ASSERT_EQ(m->outputs[0].entries.size(), 2U);
  EXPECT_EQ(m->outputs[0].entries[0].index, 0x6040);
  EXPECT_EQ(m->outputs[0].entries[1].index, 0x607A);
  EXPECT_EQ(m->outputs[0].entries[1].bit_offset, 16U);
  EXPECT_EQ(m->output_bits, 48U);
  ASSERT_EQ(m->inputs.size(), 1U);
  EXPECT_EQ(m->inputs[0].index, 0x1A00);
  EXPECT_EQ(m->input_bits, 80U);
  const auto* velocity = &m->inputs[0].entries.back();
  EXPECT_EQ(velocity->index, 0x606C);
  EXPECT_EQ(velocity->bit_offset, 48U);
  EXPECT_EQ(velocity->bit_length, 32U);
}

TEST(PdoMapping, FromSiiForASlaveWithoutMailbox) {
  Bench b("digital-io:1");
  ASSERT_TRUE(b.master->scan().ok());
  auto m = b.master->read_pdo_mapping(0);
  ASSERT_TRUE(m.ok()) << m.error().describe();
  EXPECT_EQ(m->source, PdoMapping::Source::sii);
  EXPECT_EQ(m->output_bits, 8U);
  EXPECT_EQ(m->input_bits, 8U);
  ASSERT_TRUE(m->find(0x7000, 0).has_value());
  EXPECT_EQ(m->find(0x7000, 0)->first, PdoDirection::output);
  EXPECT_EQ(m->find(0x6000, 0)->first, PdoDirection::input);
}

TEST(PdoMapping, FromSiiWhenTheSlaveAbortsObjectDoesNotExist) {
  Bench b([](slave::Segment& s) { s.add(std::make_unique<FixedMappingServo>()); });
  ASSERT_TRUE(b.master->scan().ok());
  ASSERT_TRUE(b.master->request_state(AlState::PreOp).ok());
  auto answer = b.master->sdo_upload_answer(0, 0x1C12, 0);
  ASSERT_TRUE(answer.ok()) << answer.error().describe();
  ASSERT_TRUE(std::holds_alternative<SdoAbort>(*answer));
  EXPECT_EQ(std::get<SdoAbort>(*answer).code, static_cast<std::uint32_t>(SdoAbortCode::ObjectDoesNotExist));

  const auto before = b.clock.now();
  auto m = b.master->read_pdo_mapping(0);
  ASSERT_TRUE(m.ok()) << m.error().describe();
  EXPECT_EQ(m->source, PdoMapping::Source::sii);
  EXPECT_EQ(m->output_bits, 48U);
  EXPECT_EQ(m->input_bits, 80U);
  EXPECT_LT(b.clock.now() - before, b.master->options().mailbox_timeout) << "no mailbox timeout on the way";
  // The whole configuration takes the same way.
  auto st = b.master->configure_process_data();
  ASSERT_TRUE(st.ok()) << st.error().describe();
  EXPECT_EQ(b.master->slave_info(0).pdo.source, PdoMapping::Source::sii);
}

TEST(PdoMapping, OtherAbortsAreErrorsNotAFallback) {
  Bench b("servo:1");
  ASSERT_TRUE(b.master->scan().ok());
  ASSERT_TRUE(b.master->request_state(AlState::PreOp).ok());
  // 0x1C12:00 made unreadable: "attempt to read a write-only object".
  b.segment->slave(0).objects().find(0x1C12, 0)->access = slave::access::kWrite;
  auto m = b.master->read_pdo_mapping(0);
  ASSERT_FALSE(m.ok());
  EXPECT_EQ(m.error().code, Errc::remote);
  EXPECT_NE(m.error().message.find("06010001"), std::string::npos) << m.error().message;
}

TEST(PdoMapping, SiiAndCoeAgreeForTheDefaultMapping) {
  Bench b("smart-controller:1");
  ASSERT_TRUE(b.master->scan().ok());
  ASSERT_TRUE(b.master->request_state(AlState::PreOp).ok());
  auto coe = b.master->read_pdo_mapping_coe(0);
  auto sii = b.master->read_pdo_mapping_sii(0);
  ASSERT_TRUE(coe.ok()) << coe.error().describe();
  ASSERT_TRUE(sii.ok());
  EXPECT_EQ(coe->output_bits, sii->output_bits);
  EXPECT_EQ(coe->input_bits, sii->input_bits);
  ASSERT_EQ(coe->inputs.size(), sii->inputs.size());
  for (std::size_t i = 0; i < coe->inputs.size(); ++i) {
    EXPECT_EQ(coe->inputs[i].index, sii->inputs[i].index);
    EXPECT_EQ(coe->inputs[i].bit_length, sii->inputs[i].bit_length);
  }
  // 8 axes (6 + 10 bytes) and 32 DI/DO.
  EXPECT_EQ(coe->output_bits, 8U * 48U + 32U);
  EXPECT_EQ(coe->input_bits, 8U * 80U + 32U);
}

TEST(PdoMapping, RemappedInPreOpTheImageFollows) {
  Bench b("servo:1,digital-io:1");
  ASSERT_TRUE(b.master->scan().ok());
  ASSERT_TRUE(b.master->request_state(AlState::PreOp).ok());
  auto& m = *b.master;
  // Drop velocity actual from the TxPDO (CiA 301 §7.5.2.36: subindex 0 to
  // 0, write the entries, subindex 0 to the new count).
  ASSERT_TRUE(m.sdo_write<std::uint8_t>(0, 0x1A00, 0, 0).ok());
  ASSERT_TRUE(m.sdo_write<std::uint32_t>(0, 0x1A00, 1, 0x60410010).ok());
  ASSERT_TRUE(m.sdo_write<std::uint32_t>(0, 0x1A00, 2, 0x60640020).ok());
  auto st = m.sdo_write<std::uint8_t>(0, 0x1A00, 0, 2);
  ASSERT_TRUE(st.ok()) << st.error().describe();

  st = m.request_state(AlState::Op);
  ASSERT_TRUE(st.ok()) << st.error().describe();
  const auto& info = m.slave_info(0);
  EXPECT_EQ(info.pdo.source, PdoMapping::Source::coe);
  EXPECT_EQ(info.pdo.input_bits, 48U);
  EXPECT_EQ(info.image.inputs.size, 6U);
  EXPECT_FALSE(m.slave(0).entry(0x606C, 0).ok());
  // The slave agrees: it runs in OP, the WKC is right and the statusword
  // and position come through.
  b.segment->device<slave::Servo>(0)->axis(0).set_position(4321);
  for (int i = 0; i < 5; ++i) {
    ASSERT_TRUE(b.cycle().ok());
  }
  auto position = m.slave(0).entry(0x6064, 0);
  ASSERT_TRUE(position.ok());
  EXPECT_EQ(m.slave(0).get<std::int32_t>(*position), 4321);
  EXPECT_EQ(b.segment->slave(0).state(), AlState::Op);

  // After a power loss the slave has its default mapping again; the
  // recovery writes the start-up SDOs again before SAFEOP.
  b.segment->disconnect(0);
  for (int i = 0; i < 20; ++i) {
    b.cycle();
  }
  // The emulated drive keeps its dictionary through a power cycle; a real
  // one without persistent storage forgets the remapping: do that by hand.
  const std::array<std::uint8_t, 1> three{3};
  ASSERT_EQ(b.segment->slave(0).objects().write_local(0x1A00, 0, three), 0U);
  b.segment->reconnect(0);
  int cycles = 0;
  while (!m.lost_slaves().empty() || !m.last_exchange().ok()) {
    ASSERT_LT(++cycles, 1000) << "the remapped slave did not come back";
    b.cycle();
  }
  EXPECT_EQ(b.segment->slave(0).state(), AlState::Op);
  auto count = m.sdo_read<std::uint8_t>(0, 0x1A00, 0);
  ASSERT_TRUE(count.ok());
  EXPECT_EQ(*count, 2);
  b.segment->device<slave::Servo>(0)->axis(0).set_position(-77);
  ASSERT_TRUE(b.cycle().ok());
  EXPECT_EQ(m.slave(0).get<std::int32_t>(*position), -77);
}

}  // namespace
}  // namespace sf::ethercat::master::test
