// SDO Information messages (ETG.1000.6 §5.6.3): header bits, service data of
// every opcode, fragmentation and reassembly, value text.
#include "sf/ethercat/sdo_info.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "sf/ethercat/mailbox.hpp"

namespace sf::ethercat {
namespace {

using ::testing::HasSubstr;

TEST(SdoInfoHeader, OpcodeIncompleteAndFragmentsLeft) {
  const auto bytes = SdoInfoHeader{2, true, 0x0102}.encode();
  EXPECT_EQ(bytes, (std::array<std::uint8_t, 4>{0x82, 0x00, 0x02, 0x01}));
  auto back = SdoInfoHeader::decode(bytes);
  ASSERT_TRUE(back.ok());
  EXPECT_EQ(back->opcode, 2);
  EXPECT_TRUE(back->incomplete);
  EXPECT_EQ(back->fragments_left, 0x0102);
  EXPECT_FALSE(SdoInfoHeader::decode(Bytes{0x01, 0x00, 0x00}).ok());
}

TEST(SdoInfo, EveryMessageRoundTrips) {
  const std::vector<SdoInfoMessage> messages{
      OdListRequest{OdListType::TxPdoMappable},
      OdListResponse{OdListType::All, {0x1000, 0x1018, 0x6040}},
      ObjectDescriptionRequest{0x1018},
      ObjectDescription{0x1018, 0x0000, 4, 9, "Identity"},
      EntryDescriptionRequest{0x1018, 1, 0},
      EntryDescription{0x6040, 0, 0, 0x0006, 16, 0x007F, {}, "Controlword"},
      EntryDescription{0x6040,
                       0,
                       value_info::kDefault | value_info::kMaximum,
                       0x0006,
                       16,
                       0x0007,
                       {0x00, 0x00, 0xFF, 0xFF},
                       "With default and maximum"},
      SdoInfoError{0x06020000}};
  for (const auto& m : messages) {
    const Bytes data = encode_sdo_info_data(m);
    auto back = decode_sdo_info_data(static_cast<std::uint8_t>(opcode_of(m)), data);
    ASSERT_TRUE(back.ok()) << back.error().describe();
    EXPECT_EQ(*back, m) << "opcode " << static_cast<int>(opcode_of(m));
  }
}

TEST(SdoInfo, ServiceDataLayout) {
  // Object description: index, data type, max subindex, object code, name.
  EXPECT_EQ(encode_sdo_info_data(ObjectDescription{0x1018, 0x0023, 4, 9, "Id"}),
            (Bytes{0x18, 0x10, 0x23, 0x00, 0x04, 0x09, 'I', 'd'}));
  // Entry description: index, subindex, value info, type, bits, access, name.
  EXPECT_EQ(encode_sdo_info_data(EntryDescription{0x1018, 1, 0, 0x0007, 32, 0x0007, {}, "V"}),
            (Bytes{0x18, 0x10, 0x01, 0x00, 0x07, 0x00, 0x20, 0x00, 0x07, 0x00, 'V'}));
  // A request as a whole mailbox message: CoE service 8, opcode 1, list type.
  const Bytes msg = make_sdo_info(OdListRequest{OdListType::All}, 3);
  auto coe = decode_coe(msg);
  ASSERT_TRUE(coe.ok());
  EXPECT_EQ(coe->coe.service, CoeService::SdoInformation);
  EXPECT_EQ(coe->mailbox.counter, 3);
  EXPECT_EQ(Bytes(coe->body.begin(), coe->body.end()), (Bytes{0x01, 0x00, 0x00, 0x00, 0x01, 0x00}));
}

TEST(SdoInfo, LongResponsesAreFragmentedAndReassembled) {
  OdListResponse list{OdListType::All, {}};
  for (std::uint16_t i = 0; i < 150; ++i) {
    list.indices.push_back(static_cast<std::uint16_t>(0x2000 + i));
  }
  // 2 + 300 bytes of service data, 128 - 12 = 116 per fragment: 3 fragments.
  const auto fragments = sdo_info_fragments(list, 128);
  ASSERT_EQ(fragments.size(), 3U);
  SdoInfoReassembly reassembly;
  for (std::size_t i = 0; i < fragments.size(); ++i) {
    EXPECT_LE(fragments[i].size(), 128U - kMailboxHeaderSize - kCoeHeaderSize);
    auto header = SdoInfoHeader::decode(fragments[i]).value();
    EXPECT_EQ(header.opcode, 2);
    EXPECT_EQ(header.incomplete, i + 1 < fragments.size());
    EXPECT_EQ(header.fragments_left, fragments.size() - 1 - i);
    auto got = reassembly.add(fragments[i]);
    ASSERT_TRUE(got.ok()) << got.error().describe();
    EXPECT_EQ(got->has_value(), i + 1 == fragments.size());
    if (got->has_value()) {
      EXPECT_EQ(std::get<OdListResponse>(**got), list);
    }
  }
}

TEST(SdoInfo, ReassemblyRefusesFragmentsThatDoNotContinue) {
  OdListResponse list{OdListType::All, std::vector<std::uint16_t>(100, 0x1000)};
  auto fragments = sdo_info_fragments(list, 64);
  ASSERT_GE(fragments.size(), 3U);
  SdoInfoReassembly reassembly;
  ASSERT_TRUE(reassembly.add(fragments[0]).ok());
  auto skipped = reassembly.add(fragments[2]);  // fragment 1 missing
  ASSERT_FALSE(skipped.ok());
  EXPECT_THAT(skipped.error().message, HasSubstr("does not continue"));
  // The next response starts afresh.
  auto single = sdo_info_fragments(SdoInfoError{0x06020000}, 64);
  auto error = reassembly.add(single[0]);
  ASSERT_TRUE(error.ok() && error->has_value());
  EXPECT_EQ(std::get<SdoInfoError>(**error).code, 0x06020000U);
}

TEST(SdoInfo, MalformedServiceData) {
  EXPECT_FALSE(decode_sdo_info_data(2, Bytes{0x01, 0x00, 0x00}).ok());  // odd index bytes
  EXPECT_FALSE(decode_sdo_info_data(4, Bytes{0x18, 0x10, 0x00}).ok());  // short object description
  // Value info announces a default value the data does not hold.
  EXPECT_FALSE(
      decode_sdo_info_data(6, Bytes{0x00, 0x60, 0x00, 0x10, 0x07, 0x00, 0x20, 0x00, 0x07, 0x00}).ok());
  EXPECT_FALSE(decode_sdo_info_data(9, Bytes{}).ok());  // no such opcode
}

TEST(SdoInfoValues, TextBothWays) {
  EXPECT_EQ(format_value(data_type::kUnsigned32, Bytes{0x46, 0x53, 0, 0}), "21318 (0x00005346)");
  EXPECT_EQ(format_value(data_type::kInteger16, Bytes{0xFE, 0xFF}), "-2");
  EXPECT_EQ(format_value(data_type::kVisibleString, Bytes{'a', 'b'}), "\"ab\"");
  EXPECT_EQ(format_value(data_type::kOctetString, Bytes{0x01, 0xAB}), "01 ab");
  EXPECT_EQ(parse_value(data_type::kUnsigned16, "0x1234").value(), (Bytes{0x34, 0x12}));
  EXPECT_EQ(parse_value(data_type::kInteger8, "-128").value(), (Bytes{0x80}));
  EXPECT_FALSE(parse_value(data_type::kInteger8, "128").ok());
  EXPECT_FALSE(parse_value(data_type::kUnsigned8, "-1").ok());
  EXPECT_FALSE(parse_value(data_type::kUnsigned32, "12x").ok());
  EXPECT_EQ(parse_value(data_type::kOctetString, "01 ab").value(), (Bytes{0x01, 0xAB}));
  EXPECT_EQ(data_type_from_name("i32").value(), data_type::kInteger32);
  EXPECT_FALSE(data_type_from_name("int").ok());
  EXPECT_EQ(access_text(0x0007 | 0x0008 | 0x0080), "rw (write in PREOP) TxPDO");
  EXPECT_EQ(data_type_name(0x0007), "UNSIGNED32");
}

}  // namespace
}  // namespace sf::ethercat
