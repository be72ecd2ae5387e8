// The Read service: every attribute of every NodeClass, timestamps, encodings, IndexRange and
// the service-level checks.
#include <map>

#include "space_fixture.hpp"

namespace sf::opcua::server::test {
namespace {

using ReadServiceTest = SpaceFixture;

// Attributes each NodeClass has (OPC 10000-3 §5.9 Table 7) among those this server stores.
std::map<NodeClass, std::vector<AttributeId>> attributes_by_class() {
  using A = AttributeId;
  const std::vector<A> base = {A::NodeId,      A::NodeClass, A::BrowseName,   A::DisplayName,
                               A::Description, A::WriteMask, A::UserWriteMask};
  auto with = [&base](std::vector<A> extra) {
    extra.insert(extra.begin(), base.begin(), base.end());
    return extra;
  };
  return {
      {NodeClass::Object, with({A::EventNotifier})},
      {NodeClass::Variable,
       with({A::Value, A::DataType, A::ValueRank, A::ArrayDimensions, A::AccessLevel, A::UserAccessLevel,
             A::MinimumSamplingInterval, A::Historizing, A::AccessLevelEx})},
      {NodeClass::Method, with({A::Executable, A::UserExecutable})},
      {NodeClass::ObjectType, with({A::IsAbstract})},
      {NodeClass::VariableType,
       with({A::Value, A::DataType, A::ValueRank, A::ArrayDimensions, A::IsAbstract})},
      {NodeClass::ReferenceType, with({A::IsAbstract, A::Symmetric, A::InverseName})},
      {NodeClass::DataType, with({A::IsAbstract})},
      {NodeClass::View, with({A::ContainsNoLoops, A::EventNotifier})},
  };
}

TEST_F(ReadServiceTest, EveryAttributeOfEveryNodeClass) {
  ViewSpec view;
  view.browse_name = QualifiedName(ns, "View1");
  view.parent = ns0(id::ViewsFolder);
  const auto view_id = must(space.add_view(view));
  const std::map<NodeClass, NodeId> samples = {
      {NodeClass::Object, demo},
      {NodeClass::Variable, counter},
      {NodeClass::Method, multiply},
      {NodeClass::ObjectType, ns0(id::FolderType)},
      {NodeClass::VariableType, ns0(id::BaseDataVariableType)},
      {NodeClass::ReferenceType, ns0(id::HasComponent)},
      {NodeClass::DataType, ns0(id::Double)},
      {NodeClass::View, view_id},
  };
  for (const auto& [node_class, attributes] : attributes_by_class()) {
    const NodeId& node = samples.at(node_class);
    for (std::uint32_t a = 1; a <= kMaxAttributeId; ++a) {
      const auto attribute = static_cast<AttributeId>(a);
      const bool expected = std::find(attributes.begin(), attributes.end(), attribute) != attributes.end();
      const auto result = read1(node, attribute);
      SCOPED_TRACE(to_string(node_class) + " " + std::string(attribute_name(attribute)));
      if (expected) {
        EXPECT_TRUE(result.status.is_good()) << to_string(result.status);
      } else {
        EXPECT_EQ(result.status, status::BadAttributeIdInvalid);
      }
    }
  }
}

TEST_F(ReadServiceTest, AttributeValues) {
  EXPECT_EQ(*read1(counter, AttributeId::NodeId).value.get_if<NodeId>(), counter);
  EXPECT_EQ(*read1(counter, AttributeId::NodeClass).value.get_if<std::int32_t>(), 2);
  EXPECT_EQ(*read1(counter, AttributeId::BrowseName).value.get_if<QualifiedName>(),
            QualifiedName(ns, "Counter"));
  EXPECT_EQ(read1(counter, AttributeId::DisplayName).value.get_if<LocalizedText>()->text, "Counter");
  EXPECT_EQ(*read1(counter, AttributeId::DataType).value.get_if<NodeId>(), ns0(id::Int32));
  EXPECT_EQ(*read1(counter, AttributeId::ValueRank).value.get_if<std::int32_t>(), -1);
  EXPECT_TRUE(read1(counter, AttributeId::ArrayDimensions).value.array_if<std::uint32_t>()->is_null());
  EXPECT_EQ(*read1(counter, AttributeId::AccessLevel).value.get_if<std::uint8_t>(), access_level::ReadWrite);
  EXPECT_EQ(*read1(counter, AttributeId::AccessLevelEx).value.get_if<std::uint32_t>(), 3U);
  EXPECT_EQ(*read1(counter, AttributeId::Value).value.get_if<std::int32_t>(), 7);
  EXPECT_EQ(*read1(multiply, AttributeId::Executable).value.get_if<bool>(), true);
  EXPECT_EQ(*read1(ns0(id::HasComponent), AttributeId::InverseName).value.get_if<LocalizedText>(),
            LocalizedText({}, "ComponentOf"));
  EXPECT_EQ(*read1(ns0(id::BaseDataType), AttributeId::IsAbstract).value.get_if<bool>(), true);
  EXPECT_EQ(*read1(ns0(id::Server), AttributeId::EventNotifier).value.get_if<std::uint8_t>(), 1);
  EXPECT_EQ(*read1(ns0(id::PropertyType), AttributeId::ValueRank).value.get_if<std::int32_t>(), -2);
}

TEST_F(ReadServiceTest, UserAccessComesFromTheUserContext) {
  struct ReadOnlyUser : UserContext {
    [[nodiscard]] bool can_write(const Node&, AttributeId) const override { return false; }
    [[nodiscard]] bool can_call(const Node&) const override { return false; }
  } user;
  ctx.user = &user;
  EXPECT_EQ(*read1(counter, AttributeId::UserAccessLevel).value.get_if<std::uint8_t>(),
            access_level::CurrentRead);
  EXPECT_EQ(*read1(multiply, AttributeId::UserExecutable).value.get_if<bool>(), false);
  struct Blind : UserContext {
    [[nodiscard]] bool can_read(const Node&) const override { return false; }
  } blind;
  ctx.user = &blind;
  EXPECT_EQ(read1(counter, AttributeId::Value).status, status::BadUserAccessDenied);
}

// A Value read asks the user only about reading: asking about writing too (a pattern match over
// the node's text per role) doubled the cost of every value read (bench_opcua_server).
TEST_F(ReadServiceTest, ValueReadsAskTheUserAboutReadingOnly) {
  struct Counting : UserContext {
    [[nodiscard]] bool can_read(const Node&) const override {
      ++reads;
      return true;
    }
    [[nodiscard]] bool can_write(const Node&, AttributeId) const override {
      ++writes;
      return true;
    }
    mutable int reads = 0;
    mutable int writes = 0;
  } user;
  ctx.user = &user;
  EXPECT_TRUE(read1(counter, AttributeId::Value).status.is_good());
  EXPECT_EQ(user.reads, 1);
  EXPECT_EQ(user.writes, 0);
  EXPECT_EQ(*read1(counter, AttributeId::UserAccessLevel).value.get_if<std::uint8_t>(),
            access_level::ReadWrite);
  EXPECT_EQ(user.writes, 1);
}

TEST_F(ReadServiceTest, NotReadableAndUnknown) {
  space.find_mutable_as<VariableNode>(counter)->access_level = 0;
  EXPECT_EQ(read1(counter, AttributeId::Value).status, status::BadNotReadable);
  EXPECT_EQ(read1(NodeId(ns, "nope"), AttributeId::Value).status, status::BadNodeIdUnknown);
  EXPECT_EQ(read1(counter, static_cast<AttributeId>(0)).status, status::BadAttributeIdInvalid);
  EXPECT_EQ(read1(counter, static_cast<AttributeId>(99)).status, status::BadAttributeIdInvalid);
}

TEST_F(ReadServiceTest, TimestampsToReturn) {
  DataValue stored(Variant(std::int32_t{1}));
  stored.source_timestamp = DateTime(1234);
  ASSERT_TRUE(space.set_value(counter, stored).ok());
  const DateTime now = DateTime::from_system_clock(clock.utc_now());
  auto both = read1(counter, AttributeId::Value, {}, TimestampsToReturn::Both);
  EXPECT_EQ(both.source_timestamp, DateTime(1234));
  EXPECT_EQ(both.server_timestamp, now);
  auto source = read1(counter, AttributeId::Value, {}, TimestampsToReturn::Source);
  EXPECT_EQ(source.source_timestamp, DateTime(1234));
  EXPECT_TRUE(source.server_timestamp.is_min());
  auto server = read1(counter, AttributeId::Value, {}, TimestampsToReturn::Server);
  EXPECT_TRUE(server.source_timestamp.is_min());
  EXPECT_EQ(server.server_timestamp, now);
  auto neither = read1(counter, AttributeId::Value, {}, TimestampsToReturn::Neither);
  EXPECT_TRUE(neither.source_timestamp.is_min());
  EXPECT_TRUE(neither.server_timestamp.is_min());
  // Non-Value attributes never carry a source timestamp.
  EXPECT_TRUE(read1(counter, AttributeId::DisplayName).source_timestamp.is_min());
}

TEST_F(ReadServiceTest, ServiceLevelChecks) {
  ReadRequest request;
  request.request_header.request_handle = 77;
  auto empty = read(space, request, ctx);
  EXPECT_EQ(empty.response_header.service_result, status::BadNothingToDo);
  EXPECT_EQ(empty.response_header.request_handle, 77U);

  ReadValueId item;
  item.node_id = counter;
  item.attribute_id = static_cast<std::uint32_t>(AttributeId::Value);
  request.nodes_to_read = {item, item, item};
  ctx.limits.max_nodes_per_read = 2;
  EXPECT_EQ(read(space, request, ctx).response_header.service_result, status::BadTooManyOperations);
  ctx.limits.max_nodes_per_read = 0;

  request.timestamps_to_return = TimestampsToReturn::Invalid;
  EXPECT_EQ(read(space, request, ctx).response_header.service_result, status::BadTimestampsToReturnInvalid);
  request.timestamps_to_return = TimestampsToReturn::Both;
  request.max_age = -1.0;
  EXPECT_EQ(read(space, request, ctx).response_header.service_result, status::BadMaxAgeInvalid);
  request.max_age = 0.0;
  auto ok = read(space, request, ctx);
  EXPECT_TRUE(ok.response_header.service_result.is_good());
  ASSERT_EQ(ok.results.size(), 3U);
  EXPECT_EQ(*ok.results[2].value.get_if<std::int32_t>(), 7);
}

TEST_F(ReadServiceTest, DataEncoding) {
  ReadValueId item;
  item.node_id = counter;
  item.attribute_id = static_cast<std::uint32_t>(AttributeId::Value);
  item.data_encoding = QualifiedName(0, "Default Binary");
  EXPECT_TRUE(read_attribute(space, item, TimestampsToReturn::Both, ctx).status.is_good());
  item.data_encoding = QualifiedName(0, "Default XML");
  EXPECT_EQ(read_attribute(space, item, TimestampsToReturn::Both, ctx).status,
            status::BadDataEncodingUnsupported);
  item.attribute_id = static_cast<std::uint32_t>(AttributeId::DisplayName);
  EXPECT_EQ(read_attribute(space, item, TimestampsToReturn::Both, ctx).status,
            status::BadDataEncodingInvalid);
}

TEST_F(ReadServiceTest, IndexRangeOnArraysStringsAndMatrices) {
  auto one = read1(doubles, AttributeId::Value, "1");
  ASSERT_TRUE(one.status.is_good());
  EXPECT_EQ(*one.value.array_if<double>(), (Array<double>{2.0}));
  auto span = read1(doubles, AttributeId::Value, "2:4");
  EXPECT_EQ(*span.value.array_if<double>(), (Array<double>{3.0, 4.0, 5.0}));
  auto clipped = read1(doubles, AttributeId::Value, "3:10");
  EXPECT_EQ(*clipped.value.array_if<double>(), (Array<double>{4.0, 5.0}));
  EXPECT_EQ(read1(doubles, AttributeId::Value, "5").status, status::BadIndexRangeNoData);
  EXPECT_EQ(read1(doubles, AttributeId::Value, "4:2").status, status::BadIndexRangeInvalid);
  EXPECT_EQ(read1(doubles, AttributeId::Value, "1:1").status, status::BadIndexRangeInvalid);
  EXPECT_EQ(read1(doubles, AttributeId::Value, "x").status, status::BadIndexRangeInvalid);
  EXPECT_EQ(read1(doubles, AttributeId::Value, "1,").status, status::BadIndexRangeInvalid);
  EXPECT_EQ(*read1(text, AttributeId::Value, "6:10").value.get_if<String>(), "World");
  EXPECT_EQ(read1(counter, AttributeId::Value, "0").status, status::BadIndexRangeNoData);

  auto sub = read1(matrix_var, AttributeId::Value, "0:1,1:2");
  ASSERT_TRUE(sub.status.is_good()) << to_string(sub.status);
  EXPECT_EQ(*sub.value.array_if<std::int32_t>(), (Array<std::int32_t>{2, 3, 5, 6}));
  EXPECT_EQ(sub.value.array_dimensions(), (std::vector<std::int32_t>{2, 2}));
  auto cell = read1(matrix_var, AttributeId::Value, "1,0");
  EXPECT_EQ(*cell.value.array_if<std::int32_t>(), (Array<std::int32_t>{4}));
  EXPECT_EQ(read1(matrix_var, AttributeId::Value, "1").status, status::BadIndexRangeNoData);
}

}  // namespace
}  // namespace sf::opcua::server::test
