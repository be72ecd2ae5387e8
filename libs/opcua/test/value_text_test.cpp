// Values typed on a command line: scalars and JSON arrays of a built-in type, TYPE:VALUE, and
// node references by namespace index or URI.
#include "sf/opcua/value_text.hpp"

#include <gtest/gtest.h>

#include "sf/opcua/status_codes.hpp"

namespace sf::opcua {
namespace {

TEST(ValueText, ScalarsTakeTheTypeAskedFor) {
  EXPECT_EQ(parse_variant(BuiltinType::Double, "2.5").value(), Variant(2.5));
  EXPECT_EQ(parse_variant(BuiltinType::Int32, "-7").value(), Variant(std::int32_t{-7}));
  EXPECT_EQ(parse_variant(BuiltinType::Boolean, "true").value(), Variant(true));
  EXPECT_EQ(parse_variant(BuiltinType::String, "a b").value(), Variant(String("a b")));
  EXPECT_EQ(parse_variant(BuiltinType::StatusCode, "BadNodeIdUnknown").value(),
            Variant(status::BadNodeIdUnknown));
  EXPECT_EQ(parse_variant(BuiltinType::ByteString, "0a0b").value(), Variant(ByteString(Bytes{0x0a, 0x0b})));
}

TEST(ValueText, ArraysAreJsonAndBadTextIsAnErrorThatSaysWhy) {
  EXPECT_EQ(parse_variant(BuiltinType::Int32, "[1, 2, 3]").value(), Variant(Array<std::int32_t>{1, 2, 3}));
  const auto out_of_range = parse_variant(BuiltinType::Byte, "300");
  ASSERT_FALSE(out_of_range.ok());
  EXPECT_NE(out_of_range.error().message.find("300"), std::string::npos);
  EXPECT_FALSE(parse_variant(BuiltinType::Boolean, "yes").ok());
  EXPECT_FALSE(parse_variant(BuiltinType::Int32, "[1, x]").ok());
  EXPECT_FALSE(parse_variant(BuiltinType::Null, "1").ok());
}

TEST(ValueText, TypedValuesNameTheirTypeAndBareOnesTakeTheFallback) {
  EXPECT_EQ(parse_typed_variant("Double:2.5", BuiltinType::Int32).value(), Variant(2.5));
  EXPECT_EQ(parse_typed_variant("Int16:[1,2]", BuiltinType::Null).value(),
            Variant(Array<std::int16_t>{1, 2}));
  EXPECT_EQ(parse_typed_variant("12", BuiltinType::UInt32).value(), Variant(std::uint32_t{12}));
  EXPECT_EQ(builtin_type_of_ns0(NodeId(0, id::Double)), BuiltinType::Double);
  EXPECT_EQ(builtin_type_of_ns0(NodeId(0, id::Enumeration)), BuiltinType::Int32);
  EXPECT_EQ(builtin_type_of_ns0(NodeId(2, id::Double)), BuiltinType::Null);
}

TEST(ValueText, NodeReferencesByIndexOrUri) {
  const auto by_uri = parse_node_ref("nsu=urn:smartfactory:demo;s=Demo.Counter").value();
  EXPECT_EQ(by_uri.namespace_uri, "urn:smartfactory:demo");
  EXPECT_EQ(by_uri.node_id, NodeId(0, String("Demo.Counter")));
  const auto by_index = parse_node_ref("ns=2;i=5").value();
  EXPECT_TRUE(by_index.namespace_uri.empty());
  EXPECT_EQ(by_index.node_id, NodeId(2, 5));
  EXPECT_FALSE(parse_node_ref("nsu=urn:x").ok());
}

}  // namespace
}  // namespace sf::opcua
