// Variant, DataValue, DiagnosticInfo and ExtensionObject (OPC 10000-6 §5.2.2.12 - §5.2.2.17).
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

const Guid kGuid = *Guid::parse("72962B91-FA75-4AE6-8D28-B404DC7DAF63");

ReadValueId sample_read_value_id() {
  ReadValueId r;
  r.node_id = NodeId(2, String("Demo"));
  r.attribute_id = 13;
  r.index_range = String("1:2");
  return r;
}

// One scalar of every built-in type a Variant may hold (all but Variant itself).
std::vector<Variant> every_scalar() {
  DiagnosticInfo diag;
  diag.symbolic_id = 3;
  return {Variant(true),
          Variant(std::int8_t{-8}),
          Variant(std::uint8_t{8}),
          Variant(std::int16_t{-16}),
          Variant(std::uint16_t{16}),
          Variant(std::int32_t{-32}),
          Variant(std::uint32_t{32}),
          Variant(std::int64_t{-64}),
          Variant(std::uint64_t{64}),
          Variant(1.25F),
          Variant(2.5),
          Variant("text"),
          Variant(DateTime{132'000'000'000'000'000}),
          Variant(kGuid),
          Variant(ByteString{1, 2}),
          Variant(XmlElement{String("<x/>")}),
          Variant(NodeId(2, String("n"))),
          Variant(ExpandedNodeId(NodeId(0, 85U), String("urn:u"), 3)),
          Variant(StatusCode{0x80340000}),
          Variant(QualifiedName(1, String("q"))),
          Variant(LocalizedText(String("en"), String("t"))),
          Variant(ExtensionObject::make(sample_read_value_id())),
          Variant(DataValue(Variant(7))),
          Variant(diag)};
}

TEST(VariantEncoding, NullIsOneZeroByte) {
  EXPECT_EQ(encoded(Variant{}), hex("00"));
  EXPECT_TRUE(round_trip(Variant{}).is_empty());
}

TEST(VariantEncoding, ScalarMaskIsTheBuiltInTypeId) {
  EXPECT_EQ(encoded(Variant(std::int32_t{5})), hex("06 05000000"));
  EXPECT_EQ(encoded(Variant(true)), hex("01 01"));
  EXPECT_EQ(encoded(Variant(1.0)), hex("0b 000000000000f03f"));
  EXPECT_EQ(encoded(Variant("abc")), hex("0c 03000000 616263"));
  EXPECT_EQ(encoded(Variant(StatusCode{0x80340000})), hex("13 00003480"));
  EXPECT_EQ(encoded(Variant(DiagnosticInfo{})), hex("19 00"));
}

TEST(VariantEncoding, EveryScalarTypeRoundTrips) {
  const auto scalars = every_scalar();
  ASSERT_EQ(scalars.size(), 24U);
  for (const Variant& v : scalars) {
    const Bytes bytes = encoded(v);
    ASSERT_FALSE(bytes.empty());
    EXPECT_EQ(bytes[0], static_cast<std::uint8_t>(v.type())) << to_string(v);
    EXPECT_TRUE(v.is_scalar());
    EXPECT_EQ(round_trip(v), v) << to_string(v);
  }
}

TEST(VariantEncoding, EveryArrayTypeRoundTrips) {
  const auto scalars = every_scalar();
  // An array of Variants holding every scalar, and arrays of each type built from the scalars.
  const Variant of_variants(Array<Variant>(scalars.begin(), scalars.end()));
  EXPECT_EQ(encoded(of_variants)[0], 0x80 | 24);
  EXPECT_EQ(round_trip(of_variants), of_variants);
  for (const Variant& scalar : scalars) {
    const Variant array = std::visit(
        [](const auto& s) -> Variant {
          using T = std::decay_t<decltype(s)>;
          if constexpr (requires {
                          s.get();
                          s.has_value();
                        }) {
            using V = std::decay_t<decltype(*s)>;
            return Variant(Array<V>{*s, *s});
          } else if constexpr (detail::kVariantScalar<T>) {
            return Variant(Array<T>{s, s, s});
          } else {
            return Variant{};  // arrays and Null: not produced by every_scalar()
          }
        },
        scalar.storage());
    EXPECT_TRUE(array.is_array());
    EXPECT_EQ(array.type(), scalar.type());
    EXPECT_EQ(encoded(array)[0], 0x80 | static_cast<int>(scalar.type()));
    EXPECT_EQ(round_trip(array), array) << to_string(array);
  }
}

TEST(VariantEncoding, ArraysKeepNullAndEmptyApart) {
  EXPECT_EQ(encoded(Variant(Array<std::int32_t>{1, 2})), hex("86 02000000 01000000 02000000"));
  EXPECT_EQ(encoded(Variant(Array<std::int32_t>{})), hex("86 00000000"));
  EXPECT_EQ(encoded(Variant(Array<std::int32_t>::null())), hex("86 ffffffff"));
  const Variant null_array = round_trip(Variant(Array<std::int32_t>::null()));
  ASSERT_NE(null_array.array_if<std::int32_t>(), nullptr);
  EXPECT_TRUE(null_array.array_if<std::int32_t>()->is_null());
  EXPECT_FALSE(round_trip(Variant(Array<std::int32_t>{})).array_if<std::int32_t>()->is_null());
}

TEST(VariantEncoding, MatrixCarriesDimensionsAfterTheValues) {
  auto m = Variant::matrix(Array<double>{1, 2, 3, 4, 5, 6}, {2, 3});
  ASSERT_TRUE(m.ok());
  EXPECT_TRUE(m->is_matrix());
  EXPECT_EQ(encoded(*m), hex("cb 06000000"
                             "000000000000f03f 0000000000000040 0000000000000840"
                             "0000000000001040 0000000000001440 0000000000001840"
                             "02000000 02000000 03000000"));
  const Variant back = round_trip(*m);
  EXPECT_EQ(back.array_dimensions(), (std::vector<std::int32_t>{2, 3}));
  EXPECT_EQ(back, *m);
  EXPECT_EQ(to_string(*m), "Double[2,3]:[1, 2, 3, 4, 5, 6]");
}

TEST(VariantEncoding, MatrixWithAZeroDimensionHasNoElements) {
  auto m = Variant::matrix(Array<std::int32_t>{}, {0, 4});
  ASSERT_TRUE(m.ok());
  EXPECT_EQ(round_trip(*m), *m);
  EXPECT_FALSE(Variant::matrix(Array<std::int32_t>{1}, {0, 4}).ok());
}

TEST(VariantEncoding, DimensionsMustMatchTheLength) {
  auto bad = Variant::matrix(Array<std::int32_t>{1, 2, 3}, {2, 2});
  ASSERT_FALSE(bad.ok());
  EXPECT_EQ(status_name(bad.error()), "BadEncodingError");

  // Decoding: 3 elements but dimensions 2x2.
  const Error e =
      decode_error<Variant>(hex("c6 03000000 01000000 02000000 03000000 02000000 02000000 02000000"));
  EXPECT_EQ(status_name(e), "BadDecodingError");
  EXPECT_NE(e.message.find("arrayDimensions [2,2] do not match the 3 element(s)"), std::string::npos)
      << e.message;

  // Huge dimensions whose product overflows must not wrap around to the length.
  EXPECT_EQ(status_name(decode_error<Variant>(hex("c6 01000000 01000000 02000000 00000080 ffffff7f"))),
            "BadDecodingError");
  EXPECT_EQ(status_name(decode_error<Variant>(hex("c6 01000000 01000000 02000000 00000100 00000100"))),
            "BadDecodingError");
}

TEST(VariantEncoding, EncoderRejectsInconsistentDimensions) {
  auto m = Variant::matrix(Array<std::int32_t>{1, 2, 3, 4}, {2, 2});
  ASSERT_TRUE(m.ok());
  std::get<Array<std::int32_t>>(m->storage()).push_back(5);  // now 5 elements, still 2x2
  auto bytes = encode(*m);
  ASSERT_FALSE(bytes.ok());
  EXPECT_EQ(status_name(bytes.error()), "BadEncodingError");
}

TEST(VariantEncoding, NestedVariantArraysRoundTrip) {
  const Variant inner(Array<Variant>{Variant(2.0), Variant(Array<String>{String("a"), String{}})});
  const Variant outer(Array<Variant>{
      Variant(1), inner, Variant{}, Variant(*Variant::matrix(Array<bool>{true, false, true, true}, {2, 2}))});
  EXPECT_EQ(round_trip(outer), outer);
  EXPECT_EQ(encoded(Variant(Array<Variant>{Variant(1)})), hex("98 01000000 06 01000000"));
}

TEST(VariantDecoding, RejectsMalformedMasks) {
  EXPECT_EQ(status_name(decode_error<Variant>(hex("80 00000000"))), "BadDecodingError");  // array of Null
  EXPECT_EQ(status_name(decode_error<Variant>(hex("46 05000000"))), "BadDecodingError");  // dims, no array
  const Error scalar_variant = decode_error<Variant>(hex("18 06 05000000"));
  EXPECT_EQ(status_name(scalar_variant), "BadDecodingError");
  EXPECT_NE(scalar_variant.message.find("scalar Variant"), std::string::npos) << scalar_variant.message;
  EXPECT_EQ(status_name(decode_error<Variant>(hex("20 00"))), "BadDecodingError");  // type 32
}

TEST(VariantDecoding, ReadsReservedTypeIdsAsByteString) {
  // OPC 10000-6 §5.2.2.16: ids 26..31 are accepted and their value treated as a ByteString.
  auto v = decode<Variant>(hex("1a 02000000 abcd"));
  ASSERT_TRUE(v.ok());
  ASSERT_NE(v->get_if<ByteString>(), nullptr);
  EXPECT_EQ(*v->get_if<ByteString>(), (ByteString{0xab, 0xcd}));
  auto a = decode<Variant>(hex("9f 01000000 01000000 ee"));
  ASSERT_TRUE(a.ok());
  EXPECT_EQ(a->type(), BuiltinType::ByteString);
}

static_assert(builtin_type_of<bool>() == BuiltinType::Boolean);
static_assert(builtin_type_of<double>() == BuiltinType::Double);
static_assert(builtin_type_of<LocalizedText>() == BuiltinType::LocalizedText);
static_assert(builtin_type_of<Variant>() == BuiltinType::Variant);
static_assert(builtin_type_of<DiagnosticInfo>() == BuiltinType::DiagnosticInfo);

TEST(VariantValue, AccessorsAndText) {
  const Variant v(std::int32_t{7});
  ASSERT_NE(v.get_if<std::int32_t>(), nullptr);
  EXPECT_EQ(*v.get_if<std::int32_t>(), 7);
  EXPECT_EQ(v.get_if<double>(), nullptr);
  EXPECT_EQ(v.array_length(), 1U);
  EXPECT_EQ(Variant(Array<float>{1, 2}).array_length(), 2U);
  EXPECT_EQ(to_string(v), "Int32:7");
  EXPECT_EQ(to_string(Variant("x")), "String:\"x\"");
  EXPECT_EQ(to_string(Variant(Array<std::uint8_t>{1, 2})), "Byte[]:[1, 2]");
  EXPECT_EQ(to_string(Variant{}), "Null");
  const Variant dv(DataValue(Variant(1.5)));
  ASSERT_NE(dv.get_if<DataValue>(), nullptr);
  EXPECT_EQ(dv.get_if<DataValue>()->value, Variant(1.5));
}

// ---- DataValue (§5.2.2.17) ------------------------------------------------------------------

TEST(DataValueEncoding, EachMaskBitAddsItsField) {
  DataValue dv;
  EXPECT_EQ(encoded(dv), hex("00"));
  dv.value = Variant(std::int32_t{1});
  EXPECT_EQ(encoded(dv), hex("01 06 01000000"));
  dv = DataValue{};
  dv.status = StatusCode{0x80340000};
  EXPECT_EQ(encoded(dv), hex("02 00003480"));
  dv = DataValue{};
  dv.source_timestamp = DateTime{1};
  EXPECT_EQ(encoded(dv), hex("04 0100000000000000"));
  dv = DataValue{};
  dv.server_timestamp = DateTime{2};
  EXPECT_EQ(encoded(dv), hex("08 0200000000000000"));
  dv = DataValue{};
  dv.source_picoseconds = 3;
  EXPECT_EQ(encoded(dv), hex("10 0300"));
  dv = DataValue{};
  dv.server_picoseconds = 4;
  EXPECT_EQ(encoded(dv), hex("20 0400"));
}

TEST(DataValueEncoding, AllFieldsInSpecOrder) {
  DataValue dv(Variant(true));
  dv.status = StatusCode{0x40900000};
  dv.source_timestamp = DateTime{1};
  dv.source_picoseconds = 9999;
  dv.server_timestamp = DateTime{2};
  dv.server_picoseconds = 1;
  // Value, Status, SourceTimestamp, SourcePicoseconds, ServerTimestamp, ServerPicoseconds.
  EXPECT_EQ(encoded(dv), hex("3f 01 01 00009040 0100000000000000 0f27 0200000000000000 0100"));
  EXPECT_EQ(round_trip(dv), dv);
}

TEST(DataValueDecoding, ClampsPicosecondsAndRejectsUnknownBits) {
  auto dv = decode<DataValue>(hex("30 1027 ffff"));
  ASSERT_TRUE(dv.ok());
  EXPECT_EQ(dv->source_picoseconds, 9999);
  EXPECT_EQ(dv->server_picoseconds, 9999);
  EXPECT_EQ(status_name(decode_error<DataValue>(hex("40"))), "BadDecodingError");
  EXPECT_EQ(status_name(decode_error<DataValue>(hex("05 06 01000000 01"))), "BadDecodingError");  // truncated
}

// ---- DiagnosticInfo (§5.2.2.12) ---------------------------------------------------------------

TEST(DiagnosticInfoEncoding, EachMaskBitAddsItsFieldInSpecOrder) {
  DiagnosticInfo d;
  EXPECT_EQ(encoded(d), hex("00"));
  d.symbolic_id = 1;
  d.namespace_uri = 2;
  d.localized_text = 3;
  d.locale = 4;
  d.additional_info = String("x");
  d.inner_status_code = StatusCode{0x80050000};
  // SymbolicId, NamespaceUri, Locale, LocalizedText, AdditionalInfo, InnerStatusCode.
  EXPECT_EQ(encoded(d), hex("3f 01000000 02000000 04000000 03000000 01000000 78 00000580"));
  EXPECT_EQ(round_trip(d), d);

  DiagnosticInfo only_locale;
  only_locale.locale = 9;
  EXPECT_EQ(encoded(only_locale), hex("08 09000000"));
  DiagnosticInfo only_text;
  only_text.localized_text = 9;
  EXPECT_EQ(encoded(only_text), hex("04 09000000"));
}

DiagnosticInfo nested_diagnostic(std::size_t depth) {
  DiagnosticInfo d;
  d.additional_info = String("level 0");
  DiagnosticInfo* at = &d;
  for (std::size_t i = 1; i < depth; ++i) {
    at->inner_status_code = StatusCode{0x80010000};
    at = &at->inner_diagnostic_info.emplace();
    at->symbolic_id = static_cast<std::int32_t>(i);
  }
  return d;
}

TEST(DiagnosticInfoEncoding, NestsInnerDiagnosticInfos) {
  const DiagnosticInfo d = nested_diagnostic(3);
  EXPECT_EQ(encoded(d), hex("70 07000000 6c6576656c2030 00000180 61 01000000 00000180 01 02000000"));
  const DiagnosticInfo back = round_trip(d);
  EXPECT_EQ(back, d);
  ASSERT_TRUE(back.inner_diagnostic_info);
  ASSERT_TRUE(back.inner_diagnostic_info->inner_diagnostic_info);
  EXPECT_EQ(back.inner_diagnostic_info->inner_diagnostic_info->symbolic_id, 2);
  EXPECT_EQ(round_trip(nested_diagnostic(100)), nested_diagnostic(100));
}

TEST(DiagnosticInfoDecoding, StopsAtTheDepthLimit) {
  Bytes deep(150, 0x40);  // 150 levels of "inner diagnostic info follows"
  deep.push_back(0x00);
  const Error e = decode_error<DiagnosticInfo>(deep);
  EXPECT_EQ(status_name(e), "BadEncodingLimitsExceeded");
  EXPECT_NE(e.message.find("nested deeper than the limit of 100"), std::string::npos) << e.message;

  DecodeOptions options;
  options.limits.max_depth = 5;
  EXPECT_TRUE(decode<DiagnosticInfo>(encoded(nested_diagnostic(5)), options).ok());
  EXPECT_EQ(status_name(decode_error<DiagnosticInfo>(encoded(nested_diagnostic(6)), options)),
            "BadEncodingLimitsExceeded");
  EXPECT_EQ(status_name(decode_error<DiagnosticInfo>(hex("80"))), "BadDecodingError");
}

TEST(DiagnosticInfoEncoding, EncoderStopsAtTheDepthLimitToo) {
  auto bytes = encode(nested_diagnostic(101));
  ASSERT_FALSE(bytes.ok());
  EXPECT_EQ(status_name(bytes.error()), "BadEncodingLimitsExceeded");
}

// ---- ExtensionObject (§5.2.2.15) ------------------------------------------------------------

TEST(ExtensionObjectEncoding, WithoutBody) {
  EXPECT_EQ(encoded(ExtensionObject{}), hex("0000 00"));
  const ExtensionObject eo(NodeId(0, 628U), nullptr);
  EXPECT_EQ(encoded(eo), hex("01 00 7402 00"));
  EXPECT_EQ(round_trip(eo), eo);
  EXPECT_TRUE(round_trip(eo).empty());
}

TEST(ExtensionObjectEncoding, KnownBodiesDecodeIntoTypedValues) {
  const ExtensionObject eo = ExtensionObject::make(sample_read_value_id());
  // i=628 ReadValueId_Encoding_DefaultBinary, binary body of 28 bytes.
  EXPECT_EQ(encoded(eo), hex("01 00 7402 01 1c000000"
                             "03 0200 04000000 44656d6f 0d000000 03000000 313a32 0000 ffffffff"));
  const ExtensionObject back = round_trip(eo);
  EXPECT_TRUE(back.is_decoded());
  ASSERT_NE(back.get_if<ReadValueId>(), nullptr);
  EXPECT_EQ(*back.get_if<ReadValueId>(), sample_read_value_id());
  EXPECT_EQ(back.get_if<BrowseDescription>(), nullptr);
  EXPECT_EQ(back, eo);
}

TEST(ExtensionObjectEncoding, UnknownBodiesStayOpaque) {
  const ExtensionObject eo = ExtensionObject::opaque(NodeId(2, 5000U), ByteString{1, 2, 3});
  EXPECT_EQ(encoded(eo), hex("01 02 8813 01 03000000 010203"));
  const ExtensionObject back = round_trip(eo);
  ASSERT_NE(back.opaque_body(), nullptr);
  EXPECT_EQ(*back.opaque_body(), (ByteString{1, 2, 3}));
  EXPECT_EQ(back.type_id(), NodeId(2, 5000U));

  // With an empty registry even standard structures stay opaque, byte for byte.
  const ExtensionRegistry none;
  DecodeOptions options;
  options.registry = &none;
  const Bytes typed = encoded(ExtensionObject::make(sample_read_value_id()));
  auto opaque = decode<ExtensionObject>(typed, options);
  ASSERT_TRUE(opaque.ok());
  EXPECT_FALSE(opaque->is_decoded());
  ASSERT_NE(opaque->opaque_body(), nullptr);
  EXPECT_EQ(opaque->opaque_body()->size(), 28U);
  EXPECT_EQ(encoded(*opaque), typed);
}

TEST(ExtensionObjectEncoding, XmlBody) {
  const ExtensionObject eo = ExtensionObject::xml(NodeId(0, 627U), XmlElement{String("<ReadValueId/>")});
  EXPECT_EQ(encoded(eo)[3], 0x02);
  const ExtensionObject back = round_trip(eo);
  ASSERT_NE(back.xml_body(), nullptr);
  EXPECT_EQ(back.encoding(), ExtensionObject::Encoding::Xml);
}

TEST(ExtensionObjectDecoding, RejectsBadBodies) {
  // Unknown encoding byte.
  EXPECT_EQ(status_name(decode_error<ExtensionObject>(hex("0000 03"))), "BadDecodingError");
  // Binary body without a length.
  EXPECT_EQ(status_name(decode_error<ExtensionObject>(hex("0000 01 ffffffff"))), "BadDecodingError");
  // A known body with bytes left over.
  Bytes trailing = encoded(ExtensionObject::make(sample_read_value_id()));
  trailing[5] = static_cast<std::uint8_t>(trailing[5] + 1);  // body length (after NodeId and encoding)
  trailing.push_back(0);
  const Error extra = decode_error<ExtensionObject>(trailing);
  EXPECT_EQ(status_name(extra), "BadDecodingError");
  EXPECT_NE(extra.message.find("1 trailing byte(s) after the ReadValueId body"), std::string::npos)
      << extra.message;
  // A known body that is too short: the error names the type and the field.
  Bytes short_body = hex("01 00 7402 01 05000000 03 0200 04000000");
  const Error shorter = decode_error<ExtensionObject>(short_body);
  EXPECT_EQ(status_name(shorter), "BadDecodingError");
  EXPECT_NE(shorter.message.find("{ReadValueId}.nodeId"), std::string::npos) << shorter.message;
}

TEST(ExtensionObjectValue, CopiesAreDeepAndCompareByValue) {
  ExtensionObject a = ExtensionObject::make(sample_read_value_id());
  ExtensionObject b = a;
  ASSERT_NE(b.get_if<ReadValueId>(), nullptr);
  b.get_if<ReadValueId>()->attribute_id = 1;
  EXPECT_EQ(a.get_if<ReadValueId>()->attribute_id, 13U);
  EXPECT_NE(a, b);
  b = a;
  EXPECT_EQ(a, b);
  EXPECT_NE(a, ExtensionObject::opaque(a.type_id(), ByteString{}));
  EXPECT_EQ(to_string(a),
            "ReadValueId{nodeId=ns=2;s=Demo, attributeId=13, indexRange=\"1:2\", dataEncoding=}");
}

}  // namespace
}  // namespace sf::opcua
