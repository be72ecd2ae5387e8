// The scalar built-in types: exact bytes from OPC 10000-6 §5.2.2, round trips at the edges,
// text forms.
#include <chrono>
#include <cmath>
#include <limits>

#include <gtest/gtest.h>

#include "sf/opcua/encoding.hpp"
#include "test_util.hpp"

namespace sf::opcua {
namespace {

using test::decode_error;
using test::encoded;
using test::hex;
using test::round_trip;
using test::status_name;

TEST(NumberEncoding, IsLittleEndianTwosComplementAndIeee754) {
  EXPECT_EQ(encoded(true), hex("01"));
  EXPECT_EQ(encoded(false), hex("00"));
  EXPECT_EQ(encoded(std::int8_t{-1}), hex("ff"));
  EXPECT_EQ(encoded(std::uint8_t{0xAB}), hex("ab"));
  EXPECT_EQ(encoded(std::int16_t{-2}), hex("feff"));
  EXPECT_EQ(encoded(std::uint16_t{0x1234}), hex("3412"));
  EXPECT_EQ(encoded(std::int32_t{-2}), hex("feffffff"));
  EXPECT_EQ(encoded(std::uint32_t{0x12345678}), hex("78563412"));
  EXPECT_EQ(encoded(std::int64_t{-2}), hex("feffffffffffffff"));
  EXPECT_EQ(encoded(std::uint64_t{0x0102030405060708}), hex("0807060504030201"));
  EXPECT_EQ(encoded(1.5F), hex("0000c03f"));
  EXPECT_EQ(encoded(1.0), hex("000000000000f03f"));
  EXPECT_EQ(encoded(StatusCode{0x80070000}), hex("00000780"));
}

TEST(NumberEncoding, BooleanDecodesAnyNonZeroByteAsTrue) {
  auto v = decode<bool>(hex("7f"));
  ASSERT_TRUE(v.ok());
  EXPECT_TRUE(*v);
  EXPECT_EQ(encoded(*v), hex("01"));
}

template <typename T>
void expect_limits_round_trip() {
  EXPECT_EQ(round_trip(std::numeric_limits<T>::min()), std::numeric_limits<T>::min());
  EXPECT_EQ(round_trip(std::numeric_limits<T>::max()), std::numeric_limits<T>::max());
  EXPECT_EQ(round_trip(T{0}), T{0});
}

TEST(NumberEncoding, IntegersRoundTripAtTheirLimits) {
  expect_limits_round_trip<std::int8_t>();
  expect_limits_round_trip<std::uint8_t>();
  expect_limits_round_trip<std::int16_t>();
  expect_limits_round_trip<std::uint16_t>();
  expect_limits_round_trip<std::int32_t>();
  expect_limits_round_trip<std::uint32_t>();
  expect_limits_round_trip<std::int64_t>();
  expect_limits_round_trip<std::uint64_t>();
}

TEST(NumberEncoding, FloatsKeepSpecialValues) {
  EXPECT_EQ(round_trip(std::numeric_limits<double>::infinity()), std::numeric_limits<double>::infinity());
  EXPECT_EQ(round_trip(-0.0F), -0.0F);
  EXPECT_TRUE(std::signbit(round_trip(-0.0)));
  EXPECT_EQ(round_trip(std::numeric_limits<float>::denorm_min()), std::numeric_limits<float>::denorm_min());
  EXPECT_TRUE(std::isnan(round_trip(std::numeric_limits<double>::quiet_NaN())));
}

TEST(NumberEncoding, TruncatedInputIsADecodingError) {
  const Error e = decode_error<std::uint32_t>(hex("010203"));
  EXPECT_EQ(status_name(e), "BadDecodingError");
  EXPECT_NE(e.message.find("needs 4 more byte(s)"), std::string::npos) << e.message;
}

// ---- String, ByteString, XmlElement (§5.2.2.4, §5.2.2.7, §5.2.2.8) ------------------------

TEST(StringEncoding, NullEmptyAndTextAreDistinct) {
  EXPECT_EQ(encoded(String{}), hex("ffffffff"));
  EXPECT_EQ(encoded(String("")), hex("00000000"));
  // OPC 10000-6 §5.2.2.4: UTF-8 bytes preceded by their count ("水" is three bytes).
  EXPECT_EQ(encoded(String("Hot水")), hex("06000000 486f74e6b0b4"));

  EXPECT_TRUE(round_trip(String{}).is_null());
  const String empty = round_trip(String(""));
  EXPECT_FALSE(empty.is_null());
  EXPECT_TRUE(empty.empty());
  EXPECT_EQ(round_trip(String("Hot水")), "Hot水");
  EXPECT_NE(String{}, String(""));
}

TEST(StringEncoding, LengthBeyondTheInputIsADecodingError) {
  const Error e = decode_error<String>(hex("e8030000 616263"));
  EXPECT_EQ(status_name(e), "BadDecodingError");
  EXPECT_NE(e.message.find("String length 1000"), std::string::npos) << e.message;
}

TEST(StringEncoding, NegativeLengthOtherThanMinusOneIsADecodingError) {
  EXPECT_EQ(status_name(decode_error<String>(hex("feffffff"))), "BadDecodingError");
}

TEST(StringEncoding, RespectsMaxStringLength) {
  DecodeOptions options;
  options.limits.max_string_length = 3;
  EXPECT_EQ(round_trip(String("abc"), options), "abc");
  const Error e = decode_error<String>(encoded(String("abcd")), options);
  EXPECT_EQ(status_name(e), "BadEncodingLimitsExceeded");
  EXPECT_NE(e.message.find("exceeds the limit 3"), std::string::npos) << e.message;
}

TEST(ByteStringEncoding, NullEmptyAndBytesAreDistinct) {
  EXPECT_EQ(encoded(ByteString{}), hex("ffffffff"));
  EXPECT_EQ(encoded(ByteString(Bytes{})), hex("00000000"));
  EXPECT_EQ(encoded(ByteString{0xde, 0xad}), hex("02000000 dead"));
  EXPECT_TRUE(round_trip(ByteString{}).is_null());
  EXPECT_FALSE(round_trip(ByteString(Bytes{})).is_null());
  EXPECT_EQ(round_trip(ByteString{1, 2, 3}), (ByteString{1, 2, 3}));
  EXPECT_EQ(ByteString::from_text("ab"), (ByteString{0x61, 0x62}));
}

TEST(XmlElementEncoding, IsEncodedLikeAString) {
  const XmlElement xml{String("<a/>")};
  EXPECT_EQ(encoded(xml), hex("04000000 3c612f3e"));
  EXPECT_EQ(round_trip(xml), xml);
  EXPECT_TRUE(round_trip(XmlElement{}).xml.is_null());
}

// ---- Guid (§5.2.2.6) ----------------------------------------------------------------------

TEST(GuidEncoding, MatchesThePart6Example) {
  auto g = Guid::parse("72962B91-FA75-4AE6-8D28-B404DC7DAF63");
  ASSERT_TRUE(g.ok());
  EXPECT_EQ(g->data1, 0x72962B91U);
  EXPECT_EQ(g->data2, 0xFA75U);
  EXPECT_EQ(g->data3, 0x4AE6U);
  // Data1..Data3 little-endian, Data4 in order (OPC 10000-6 §5.2.2.6, Figure 8 in v1.05).
  EXPECT_EQ(encoded(*g), hex("912b9672 75fa e64a 8d28b404dc7daf63"));
  EXPECT_EQ(round_trip(*g), *g);
  EXPECT_EQ(to_string(*g), "72962B91-FA75-4AE6-8D28-B404DC7DAF63");
}

TEST(GuidText, AcceptsBracesAndLowerCaseAndRejectsGarbage) {
  auto braced = Guid::parse("{72962b91-fa75-4ae6-8d28-b404dc7daf63}");
  ASSERT_TRUE(braced.ok());
  EXPECT_EQ(to_string(*braced), "72962B91-FA75-4AE6-8D28-B404DC7DAF63");
  EXPECT_FALSE(Guid::parse("72962B91-FA75-4AE6-8D28-B404DC7DAF6").ok());
  EXPECT_FALSE(Guid::parse("72962B91+FA75-4AE6-8D28-B404DC7DAF63").ok());
  EXPECT_FALSE(Guid::parse("X2962B91-FA75-4AE6-8D28-B404DC7DAF63").ok());
  EXPECT_TRUE(Guid{}.is_null());
}

// ---- NodeId (§5.2.2.9) --------------------------------------------------------------------

TEST(NodeIdEncoding, MatchesThePart6Examples) {
  EXPECT_EQ(encoded(NodeId(0, 72U)), hex("00 48"));                                      // two-byte form
  EXPECT_EQ(encoded(NodeId(5, 1025U)), hex("01 05 0104"));                               // four-byte form
  EXPECT_EQ(encoded(NodeId(1, String("Hot水"))), hex("03 0100 06000000 486f74e6b0b4"));  // string
}

TEST(NodeIdEncoding, ChoosesTheShortestNumericForm) {
  EXPECT_EQ(encoded(NodeId(0, 0U)), hex("00 00"));
  EXPECT_EQ(encoded(NodeId(0, 255U)), hex("00 ff"));
  EXPECT_EQ(encoded(NodeId(0, 256U)), hex("01 00 0001"));
  EXPECT_EQ(encoded(NodeId(1, 0U)), hex("01 01 0000"));
  EXPECT_EQ(encoded(NodeId(255, 65535U)), hex("01 ff ffff"));
  EXPECT_EQ(encoded(NodeId(256, 1U)), hex("02 0001 01000000"));
  EXPECT_EQ(encoded(NodeId(0, 65536U)), hex("02 0000 00000100"));
  EXPECT_EQ(encoded(NodeId(65535, 0xFFFFFFFFU)), hex("02 ffff ffffffff"));
}

TEST(NodeIdEncoding, EveryIdentifierTypeRoundTrips) {
  const Guid g = *Guid::parse("72962B91-FA75-4AE6-8D28-B404DC7DAF63");
  const std::vector<NodeId> ids = {
      NodeId(0, 85U),          NodeId(7, 1000U),          NodeId(300, 70000U), NodeId(2, String("Demo")),
      NodeId(2, String("")),   NodeId(2, String{}),       NodeId(3, g),        NodeId(4, ByteString{1, 2, 3}),
      NodeId(4, ByteString{}), NodeId(65535, String("x"))};
  for (const NodeId& id : ids) {
    EXPECT_EQ(round_trip(id), id) << to_string(id);
  }
  EXPECT_EQ(encoded(NodeId(3, g)), hex("04 0300 912b967275fae64a8d28b404dc7daf63"));
  EXPECT_EQ(encoded(NodeId(4, ByteString{1, 2, 3})), hex("05 0400 03000000 010203"));
}

TEST(NodeIdEncoding, DecodesLongFormsOfSmallIdsAndReEncodesThemShort) {
  auto id = decode<NodeId>(hex("02 0000 48000000"));
  ASSERT_TRUE(id.ok());
  EXPECT_EQ(*id, NodeId(0, 72U));
  EXPECT_EQ(encoded(*id), hex("00 48"));
}

TEST(NodeIdEncoding, RejectsUnknownFormatsAndExpandedFlags) {
  const Error unknown = decode_error<NodeId>(hex("06 0000"));
  EXPECT_EQ(status_name(unknown), "BadDecodingError");
  EXPECT_NE(unknown.message.find("unknown format 0x06"), std::string::npos) << unknown.message;
  EXPECT_EQ(status_name(decode_error<NodeId>(hex("80 48"))), "BadDecodingError");
  EXPECT_EQ(status_name(decode_error<NodeId>(hex("01 05"))), "BadDecodingError");  // truncated
}

TEST(NodeIdText, FormatsAndParsesEveryIdentifierType) {
  EXPECT_EQ(to_string(NodeId(0, 85U)), "i=85");
  EXPECT_EQ(to_string(NodeId(2, String("Demo"))), "ns=2;s=Demo");
  EXPECT_EQ(to_string(NodeId(1, *Guid::parse("72962B91-FA75-4AE6-8D28-B404DC7DAF63"))),
            "ns=1;g=72962B91-FA75-4AE6-8D28-B404DC7DAF63");
  EXPECT_EQ(to_string(NodeId(1, ByteString{0, 1, 2, 3})), "ns=1;b=AAECAw==");

  for (std::string_view text : {"i=85", "ns=2;s=Demo", "ns=1;g=72962B91-FA75-4AE6-8D28-B404DC7DAF63",
                                "ns=1;b=AAECAw==", "ns=65535;i=4294967295", "s=with;semicolon"}) {
    auto id = NodeId::parse(text);
    ASSERT_TRUE(id.ok()) << text;
    EXPECT_EQ(to_string(*id), text);
  }
  for (std::string_view bad :
       {"", "x=1", "i=", "i=-1", "i=4294967296", "ns=65536;i=1", "ns=1", "ns=a;i=1", "g=nope", "b=%%%%"}) {
    EXPECT_FALSE(NodeId::parse(bad).ok()) << bad;
  }
}

TEST(NodeIdValue, KnowsNullAndHashesByValue) {
  EXPECT_TRUE(NodeId{}.is_null());
  EXPECT_TRUE(NodeId(0, String("")).is_null());
  EXPECT_FALSE(NodeId(1, 0U).is_null());
  EXPECT_FALSE(NodeId(0, 85U).is_null());
  EXPECT_EQ(NodeId(2, String("a")).hash(), NodeId(2, String("a")).hash());
  EXPECT_NE(NodeId(2, 5U), NodeId(3, 5U));
  EXPECT_NE(NodeId(0, String("5")), NodeId(0, 5U));
  std::unordered_map<NodeId, int> map{{NodeId(0, 85U), 1}, {NodeId(2, String("x")), 2}};
  EXPECT_EQ(map.at(NodeId(2, String("x"))), 2);
}

// ---- ExpandedNodeId (§5.2.2.10) -----------------------------------------------------------

TEST(ExpandedNodeIdEncoding, SetsFlagsForNamespaceUriAndServerIndex) {
  EXPECT_EQ(encoded(ExpandedNodeId(NodeId(0, 85U))), hex("00 55"));
  EXPECT_EQ(encoded(ExpandedNodeId(NodeId(0, 85U), String("urn:x"))), hex("80 55 05000000 75726e3a78"));
  EXPECT_EQ(encoded(ExpandedNodeId(NodeId(0, 85U), String{}, 2)), hex("40 55 02000000"));
  EXPECT_EQ(encoded(ExpandedNodeId(NodeId(2, String("a")), String("u"), 1)),
            hex("c3 0200 01000000 61 01000000 75 01000000"));
  for (const auto& id : {ExpandedNodeId(NodeId(0, 85U)), ExpandedNodeId(NodeId(0, 85U), String("urn:x")),
                         ExpandedNodeId(NodeId(9, 1234567U), String("u"), 7)}) {
    EXPECT_EQ(round_trip(id), id);
  }
}

TEST(ExpandedNodeIdText, NamesServerAndNamespaceUri) {
  EXPECT_EQ(to_string(ExpandedNodeId(NodeId(2, String("Demo")))), "ns=2;s=Demo");
  EXPECT_EQ(to_string(ExpandedNodeId(NodeId(0, 85U), String("http://x/a;b"), 2)),
            "svr=2;nsu=http://x/a%3Bb;i=85");
  EXPECT_TRUE(ExpandedNodeId(NodeId(0, 85U)).is_local());
}

// ---- DateTime (§5.2.2.5) ------------------------------------------------------------------

TEST(DateTimeValue, CountsHundredNanosecondsSince1601) {
  using std::chrono::system_clock;
  EXPECT_EQ(DateTime::from_system_clock(system_clock::time_point{}).ticks(), 116'444'736'000'000'000);
  const auto t =
      system_clock::time_point{std::chrono::seconds{1'714'564'800} + std::chrono::milliseconds{123}};
  const DateTime dt = DateTime::from_system_clock(t);
  EXPECT_EQ(dt.ticks(), 116'444'736'000'000'000 + 17'145'648'001'230'000);
  EXPECT_EQ(dt.to_system_clock(), t);
  EXPECT_EQ(to_string(dt), "2024-05-01T12:00:00.1230000Z");
  EXPECT_EQ(to_string(DateTime::from_unix_seconds(0)), "1970-01-01T00:00:00Z");
  EXPECT_EQ(to_string(DateTime::min()), "1601-01-01T00:00:00Z");
  EXPECT_EQ(encoded(DateTime{0x0102030405060708}), hex("0807060504030201"));
  EXPECT_EQ(round_trip(DateTime{-5}), DateTime{-5});  // kept raw, even when invalid
}

TEST(DateTimeValue, ClampsToTheRangeOfTheSpec) {
  EXPECT_EQ(DateTime::from_unix_seconds(-20'000'000'000), DateTime::min());  // before 1601
  EXPECT_EQ(DateTime::from_unix_seconds(300'000'000'000), DateTime::max());  // after 9999
  EXPECT_EQ(DateTime::from_unix_seconds(253'402'300'798).ticks(),            // 9999-12-31 23:59:58
            116'444'736'000'000'000 + 2'534'023'007'980'000'000);
  EXPECT_EQ(DateTime::from_unix_seconds(253'402'300'799), DateTime::max());  // 9999-12-31 23:59:59
  EXPECT_EQ(DateTime::min().to_system_clock(), std::chrono::system_clock::time_point::min());
  EXPECT_EQ(DateTime::max().to_system_clock(), std::chrono::system_clock::time_point::max());
  EXPECT_TRUE(DateTime{}.is_min());
}

// ---- QualifiedName, LocalizedText (§5.2.2.13, §5.2.2.14) ----------------------------------

TEST(QualifiedNameEncoding, IsNamespaceIndexThenName) {
  const QualifiedName name(2, String("Temperature"));
  EXPECT_EQ(encoded(name), hex("0200 0b000000 54656d7065726174757265"));
  EXPECT_EQ(round_trip(name), name);
  EXPECT_EQ(to_string(name), "2:Temperature");
  EXPECT_EQ(to_string(QualifiedName(0, String("Objects"))), "Objects");
  EXPECT_EQ(encoded(QualifiedName{}), hex("0000 ffffffff"));
}

TEST(LocalizedTextEncoding, MaskNamesThePresentFields) {
  EXPECT_EQ(encoded(LocalizedText{}), hex("00"));
  EXPECT_EQ(encoded(LocalizedText(String("en"), String{})), hex("01 02000000 656e"));
  EXPECT_EQ(encoded(LocalizedText(String{}, String("Hi"))), hex("02 02000000 4869"));
  EXPECT_EQ(encoded(LocalizedText(String("en"), String("Hi"))), hex("03 02000000 656e 02000000 4869"));
  EXPECT_EQ(encoded(LocalizedText(String(""), String(""))), hex("03 00000000 00000000"));
  for (const auto& text :
       {LocalizedText{}, LocalizedText(String("en"), String{}), LocalizedText(String{}, String("Hi")),
        LocalizedText(String("de"), String("Süß"))}) {
    EXPECT_EQ(round_trip(text), text);
  }
  EXPECT_EQ(to_string(LocalizedText(String("en"), String("Hi"))), "\"Hi\"@en");
}

TEST(LocalizedTextEncoding, RejectsUnknownMaskBits) {
  const Error e = decode_error<LocalizedText>(hex("04"));
  EXPECT_EQ(status_name(e), "BadDecodingError");
  EXPECT_NE(e.message.find("mask 0x04"), std::string::npos) << e.message;
}

TEST(Base64, RoundTripsAndRejectsMalformedText) {
  for (const Bytes& b : {Bytes{}, Bytes{1}, Bytes{1, 2}, Bytes{1, 2, 3}, Bytes{0xff, 0xfe, 0xfd, 0xfc}}) {
    auto back = base64_decode(base64_encode(b));
    ASSERT_TRUE(back.ok());
    EXPECT_EQ(*back, b);
  }
  EXPECT_EQ(base64_encode(hex("000102030405060708090a0b0c0d0e0f")), "AAECAwQFBgcICQoLDA0ODw==");
  EXPECT_FALSE(base64_decode("abc").ok());
  EXPECT_FALSE(base64_decode("a=bc").ok());
  EXPECT_FALSE(base64_decode("ab=c").ok());
  EXPECT_FALSE(base64_decode("ab==ab==").ok());
}

}  // namespace
}  // namespace sf::opcua
