// The built-in type behind a DataType, through the HasSubtype hierarchy (OPC 10000-3 §5.8.3):
// what `opcua write` and `opcua call` type a bare value by.
#include "sf/opcua/server/ns0.hpp"
#include "sf/opcua/value_text.hpp"
#include "space_fixture.hpp"

namespace sf::opcua::server::test {
namespace {

class DataTypesTest : public ::testing::Test {
 protected:
  void SetUp() override { ASSERT_TRUE(build_namespace0(space).ok()); }
  AddressSpace space;
};

TEST_F(DataTypesTest, SubtypesOfBuiltinTypesAreTheirBuiltinType) {
  // Without the hierarchy a Duration is unknown: the bare mapping only knows ids 1..25.
  EXPECT_EQ(builtin_type_of_ns0(ns0(id::Duration)), BuiltinType::Null);
  EXPECT_EQ(builtin_type_of(space, ns0(id::Duration)), BuiltinType::Double);
  EXPECT_EQ(builtin_type_of(space, ns0(id::UtcTime)), BuiltinType::DateTime);
  EXPECT_EQ(builtin_type_of(space, ns0(id::Counter)), BuiltinType::UInt32);
  EXPECT_EQ(builtin_type_of(space, ns0(id::LocaleId)), BuiltinType::String);
  EXPECT_EQ(builtin_type_of(space, ns0(id::Double)), BuiltinType::Double);
  EXPECT_EQ(builtin_type_of(ns0(id::Duration)), BuiltinType::Double);  // namespace 0 alone
}

TEST_F(DataTypesTest, EnumerationsAreInt32AndStructuresAndAbstractTypesHaveNone) {
  EXPECT_EQ(builtin_type_of(space, ns0(id::ServerState)), BuiltinType::Int32);
  EXPECT_EQ(builtin_type_of(space, ns0(id::Range)), BuiltinType::Null);
  EXPECT_EQ(builtin_type_of(space, ns0(id::Number)), BuiltinType::Null);
  EXPECT_EQ(builtin_type_of(space, NodeId(5, 1234)), BuiltinType::Null);  // not in the space
}

TEST_F(DataTypesTest, AServersOwnSubtypeIsFoundThroughItsSupertypes) {
  const std::uint16_t ns = space.add_namespace("urn:test:types");
  DataTypeSpec milliseconds;
  milliseconds.node_id = NodeId(ns, String("CycleTime"));
  milliseconds.browse_name = QualifiedName(ns, "CycleTime");
  milliseconds.parent = ns0(id::Duration);
  ASSERT_TRUE(space.add_data_type(milliseconds).ok());
  EXPECT_EQ(builtin_type_of(space, milliseconds.node_id), BuiltinType::Double);
  EXPECT_EQ(builtin_type_of(milliseconds.node_id), BuiltinType::Null);  // namespace 0 does not know it
}

}  // namespace
}  // namespace sf::opcua::server::test
