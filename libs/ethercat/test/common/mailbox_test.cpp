// Mailbox header, mailbox error, CoE header and emergency codecs.
#include "sf/ethercat/mailbox.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

namespace sf::ethercat {
namespace {

using ::testing::HasSubstr;

TEST(MailboxHeader, BitLayoutOfEtg1000_4Table29) {
  MailboxHeader h;
  h.length = 0x000A;
  h.address = 0x1001;
  h.channel = 0x3F;
  h.priority = 2;
  h.type = MailboxType::CoE;
  h.counter = 5;
  const std::array<std::uint8_t, 6> expected{0x0A, 0x00, 0x01, 0x10, 0xBF, 0x53};
  EXPECT_EQ(h.encode(), expected);
  auto back = MailboxHeader::decode(expected);
  ASSERT_TRUE(back);
  EXPECT_EQ(*back, h);
}

TEST(MailboxHeader, FieldsAreMaskedToTheirWidth) {
  MailboxHeader h;
  h.channel = 0xFF;
  h.priority = 0xFF;
  h.counter = 0xFF;
  h.type = static_cast<MailboxType>(0xFF);
  const auto b = h.encode();
  EXPECT_EQ(b[4], 0xFF);
  EXPECT_EQ(b[5], 0x7F);  // reserved bit 7 stays clear
  auto back = MailboxHeader::decode(b);
  ASSERT_TRUE(back);
  EXPECT_EQ(back->counter, 7);
  EXPECT_EQ(static_cast<unsigned>(back->type), 15U);
  EXPECT_EQ(back->type, MailboxType::VoE);
}

TEST(MailboxHeader, CounterSequenceSkipsZero) {
  EXPECT_EQ(next_mailbox_counter(0), 1);
  EXPECT_EQ(next_mailbox_counter(1), 2);
  EXPECT_EQ(next_mailbox_counter(6), 7);
  EXPECT_EQ(next_mailbox_counter(7), 1);
}

TEST(Mailbox, EncodeSetsLengthAndDecodeIgnoresTheRestOfTheBuffer) {
  MailboxHeader h;
  h.type = MailboxType::FoE;
  h.counter = 3;
  const Bytes data{1, 2, 3};
  Bytes buffer = encode_mailbox(h, data);
  ASSERT_EQ(buffer.size(), 9U);
  EXPECT_EQ(buffer[0], 3);
  buffer.resize(128, 0xEE);  // the unused rest of a SyncManager buffer
  auto m = decode_mailbox(buffer);
  ASSERT_TRUE(m) << m.error().describe();
  EXPECT_EQ(m->header.type, MailboxType::FoE);
  EXPECT_EQ(m->header.length, 3);
  EXPECT_EQ(Bytes(m->data.begin(), m->data.end()), data);
}

TEST(Mailbox, RejectsShortHeaderAndLengthBeyondBuffer) {
  const Bytes five(5, 0);
  auto short_header = decode_mailbox(five);
  ASSERT_FALSE(short_header);
  EXPECT_THAT(short_header.error().message, HasSubstr("needs 6 bytes"));

  Bytes buf = encode_mailbox(MailboxHeader{}, Bytes(4));
  buf[0] = 5;
  auto long_length = decode_mailbox(buf);
  ASSERT_FALSE(long_length);
  EXPECT_THAT(long_length.error().message, HasSubstr("mailbox length 5 exceeds the 4 bytes"));
}

TEST(MailboxError, ReplyLayoutAndDecode) {
  const Bytes reply = encode_mailbox_error(MailboxError::UnsupportedProtocol, 2, 0x1001);
  EXPECT_EQ(reply, (Bytes{0x04, 0x00, 0x01, 0x10, 0x00, 0x20, 0x01, 0x00, 0x02, 0x00}));
  auto m = decode_mailbox(reply);
  ASSERT_TRUE(m);
  EXPECT_EQ(m->header.type, MailboxType::Err);
  auto e = decode_mailbox_error(m->data);
  ASSERT_TRUE(e);
  EXPECT_EQ(*e, MailboxError::UnsupportedProtocol);
  EXPECT_THAT(describe(*e), HasSubstr("not supported"));

  EXPECT_FALSE(decode_mailbox_error(Bytes{0x01, 0x00, 0x02}));
  auto wrong_type = decode_mailbox_error(Bytes{0x02, 0x00, 0x02, 0x00});
  ASSERT_FALSE(wrong_type);
  EXPECT_THAT(wrong_type.error().message, HasSubstr("0x0002"));
}

TEST(CoeHeader, NumberAndService) {
  const CoeHeader h{0x0101, CoeService::TxPdo};
  EXPECT_EQ(h.encode(), 0x4101);
  auto back = CoeHeader::decode(0x4101);
  ASSERT_TRUE(back);
  EXPECT_EQ(*back, h);
  EXPECT_EQ((CoeHeader{0, CoeService::SdoRequest}.encode()), 0x2000);
  EXPECT_EQ(CoeHeader::decode(0x2E00)->number, 0);  // reserved bits 11:9 ignored
  EXPECT_FALSE(CoeHeader::decode(0x0000));
  EXPECT_FALSE(CoeHeader::decode(0x9000));
  EXPECT_EQ(to_string(CoeService::SdoInformation), "SDO information");
}

TEST(Coe, WrapsBodyAndRejectsOtherMailboxTypes) {
  MailboxHeader h;
  h.counter = 1;
  h.type = MailboxType::EoE;  // overridden: encode_coe always writes CoE
  const Bytes msg = encode_coe(h, CoeHeader{0, CoeService::Emergency}, Bytes{9, 8, 7});
  auto coe = decode_coe(msg);
  ASSERT_TRUE(coe) << coe.error().describe();
  EXPECT_EQ(coe->mailbox.type, MailboxType::CoE);
  EXPECT_EQ(coe->mailbox.length, 5);
  EXPECT_EQ(coe->coe.service, CoeService::Emergency);
  EXPECT_EQ(Bytes(coe->body.begin(), coe->body.end()), (Bytes{9, 8, 7}));

  Bytes foe = msg;
  foe[5] = static_cast<std::uint8_t>((foe[5] & 0xF0U) | 0x04U);
  auto not_coe = decode_coe(foe);
  ASSERT_FALSE(not_coe);
  EXPECT_THAT(not_coe.error().message, HasSubstr("FoE"));

  MailboxHeader empty;
  auto no_coe_header = decode_coe(encode_mailbox(empty, Bytes{0x00}));
  ASSERT_FALSE(no_coe_header);
  EXPECT_THAT(no_coe_header.error().message, HasSubstr("no room for the CoE header"));

  Bytes bad_service = msg;
  bad_service[7] = 0xF0;
  EXPECT_FALSE(decode_coe(bad_service));
}

TEST(CoeEmergency, RoundTripAndShortBody) {
  const CoeEmergency e{0x8130, 0x11, {1, 2, 3, 4, 5}};
  const Bytes body = e.encode();
  EXPECT_EQ(body, (Bytes{0x30, 0x81, 0x11, 1, 2, 3, 4, 5}));
  auto back = CoeEmergency::decode(body);
  ASSERT_TRUE(back);
  EXPECT_EQ(*back, e);
  auto short_body = CoeEmergency::decode(ByteSpan(body).first(7));
  ASSERT_FALSE(short_body);
  EXPECT_THAT(short_body.error().message, HasSubstr("CoE emergency"));
}

}  // namespace
}  // namespace sf::ethercat
