// The Write service: access levels, the user hook, type checks, IndexRange writes, WriteMask and
// the write callback.
#include "space_fixture.hpp"

namespace sf::opcua::server::test {
namespace {

using WriteServiceTest = SpaceFixture;

TEST_F(WriteServiceTest, WritesAValueAndStampsIt) {
  clock.advance(std::chrono::seconds(10));
  ASSERT_EQ(write1(counter, AttributeId::Value, Variant(std::int32_t{99})), StatusCode());
  auto v = space.value(counter);
  EXPECT_EQ(*v->value.get_if<std::int32_t>(), 99);
  EXPECT_EQ(v->source_timestamp, DateTime::from_system_clock(clock.utc_now()));
}

TEST_F(WriteServiceTest, AccessLevelAndUserChecks) {
  EXPECT_EQ(write1(temperature, AttributeId::Value, Variant(1.0)), status::BadNotWritable);
  space.find_mutable_as<VariableNode>(counter)->user_access_level = access_level::CurrentRead;
  EXPECT_EQ(write1(counter, AttributeId::Value, Variant(std::int32_t{1})), status::BadUserAccessDenied);
  space.find_mutable_as<VariableNode>(counter)->user_access_level = access_level::ReadWrite;
  struct ReadOnlyUser : UserContext {
    [[nodiscard]] bool can_write(const Node&, AttributeId) const override { return false; }
  } user;
  ctx.user = &user;
  EXPECT_EQ(write1(counter, AttributeId::Value, Variant(std::int32_t{1})), status::BadUserAccessDenied);
  ctx.user = nullptr;
  EXPECT_EQ(write1(NodeId(ns, "nope"), AttributeId::Value, Variant(1.0)), status::BadNodeIdUnknown);
  EXPECT_EQ(write1(demo, AttributeId::Value, Variant(1.0)), status::BadAttributeIdInvalid);
  EXPECT_EQ(write1(counter, static_cast<AttributeId>(0), Variant(1.0)), status::BadAttributeIdInvalid);
}

TEST_F(WriteServiceTest, StatusAndTimestampsNeedTheirAccessBits) {
  WriteValue item;
  item.node_id = counter;
  item.attribute_id = static_cast<std::uint32_t>(AttributeId::Value);
  item.value = DataValue(Variant(std::int32_t{5}));
  item.value.status = status::BadOutOfRange;
  EXPECT_EQ(write_attribute(space, item, ctx), status::BadWriteNotSupported);
  item.value.status = StatusCode();
  item.value.source_timestamp = DateTime(5);
  EXPECT_EQ(write_attribute(space, item, ctx), status::BadWriteNotSupported);
  space.find_mutable_as<VariableNode>(counter)->access_level |= access_level::TimestampWrite;
  EXPECT_EQ(write_attribute(space, item, ctx), StatusCode());
  EXPECT_EQ(space.value(counter)->source_timestamp, DateTime(5));
}

TEST_F(WriteServiceTest, TypeChecks) {
  EXPECT_EQ(write1(counter, AttributeId::Value, Variant(1.5)), status::BadTypeMismatch);
  EXPECT_EQ(write1(counter, AttributeId::Value, Variant(std::uint32_t{1})), status::BadTypeMismatch);
  EXPECT_EQ(write1(counter, AttributeId::Value, Variant(std::vector<std::int32_t>{1, 2})),
            status::BadTypeMismatch);
  EXPECT_EQ(write1(counter, AttributeId::Value, Variant()), status::BadTypeMismatch);
  EXPECT_EQ(write1(doubles, AttributeId::Value, Variant(1.0)), status::BadTypeMismatch);
  EXPECT_EQ(write1(doubles, AttributeId::Value, Variant(std::vector<double>{9.0})), StatusCode());
  EXPECT_EQ(write1(text, AttributeId::Value, Variant(LocalizedText({}, "x"))), status::BadTypeMismatch);

  // Subtypes: a Number variable takes any number; Duration takes Double; enums take Int32.
  const auto number = add_var("Number", ns0(id::Number), Variant(1.0), access_level::ReadWrite);
  EXPECT_EQ(write1(number, AttributeId::Value, Variant(std::int16_t{3})), StatusCode());
  EXPECT_EQ(write1(number, AttributeId::Value, Variant("three")), status::BadTypeMismatch);
  const auto duration = add_var("Duration", ns0(id::Duration), Variant(1.0), access_level::ReadWrite);
  EXPECT_EQ(write1(duration, AttributeId::Value, Variant(250.0)), StatusCode());
  const auto state =
      add_var("State", ns0(id::ServerState), Variant(std::int32_t{0}), access_level::ReadWrite);
  EXPECT_EQ(write1(state, AttributeId::Value, Variant(std::int32_t{4})), StatusCode());
  const auto any = add_var("Any", ns0(id::BaseDataType), Variant(), access_level::ReadWrite, value_rank::Any);
  EXPECT_EQ(write1(any, AttributeId::Value, Variant("anything")), StatusCode());
  EXPECT_EQ(write1(any, AttributeId::Value, Variant()), StatusCode());

  // Structures by their DataTypeEncoding; Structure takes them all.
  const auto range = add_var("Range", ns0(id::Range), Variant(ExtensionObject::make(Range{0.0, 1.0})),
                             access_level::ReadWrite);
  EXPECT_EQ(write1(range, AttributeId::Value, Variant(ExtensionObject::make(Range{2.0, 3.0}))), StatusCode());
  EXPECT_EQ(write1(range, AttributeId::Value, Variant(ExtensionObject::make(EUInformation{}))),
            status::BadTypeMismatch);
  const auto structure = add_var("Structure", ns0(id::Structure), Variant(), access_level::ReadWrite);
  EXPECT_EQ(write1(structure, AttributeId::Value, Variant(ExtensionObject::make(Range{}))), StatusCode());

  // ArrayDimensions bound array lengths.
  space.find_mutable_as<VariableNode>(doubles)->array_dimensions = {3};
  EXPECT_EQ(write1(doubles, AttributeId::Value, Variant(std::vector<double>{1, 2, 3, 4})),
            status::BadTypeMismatch);
  EXPECT_EQ(write1(doubles, AttributeId::Value, Variant(std::vector<double>{1, 2, 3})), StatusCode());
  // Matrices need their rank.
  auto matrix = Variant::matrix(Array<std::int32_t>{1, 2, 3, 4}, {2, 2});
  EXPECT_EQ(write1(matrix_var, AttributeId::Value, *matrix), StatusCode());
  EXPECT_EQ(write1(matrix_var, AttributeId::Value, Variant(std::vector<std::int32_t>{1, 2})),
            status::BadTypeMismatch);
}

TEST_F(WriteServiceTest, IndexRangeWrites) {
  EXPECT_EQ(write1(doubles, AttributeId::Value, Variant(std::vector<double>{20.0, 30.0}), "1:2"),
            StatusCode());
  EXPECT_EQ(*space.value(doubles)->value.array_if<double>(), (Array<double>{1.0, 20.0, 30.0, 4.0, 5.0}));
  EXPECT_EQ(write1(doubles, AttributeId::Value, Variant(std::vector<double>{1.0}), "1:2"),
            status::BadTypeMismatch);
  EXPECT_EQ(write1(doubles, AttributeId::Value, Variant(std::vector<double>{1.0, 2.0}), "4:5"),
            status::BadIndexRangeNoData);
  EXPECT_EQ(write1(doubles, AttributeId::Value, Variant(std::vector<double>{1.0}), "2:1"),
            status::BadIndexRangeInvalid);
  EXPECT_EQ(write1(doubles, AttributeId::Value, Variant(std::vector<std::int32_t>{1}), "0"),
            status::BadTypeMismatch);
  EXPECT_EQ(write1(text, AttributeId::Value, Variant("J"), "0"), StatusCode());
  EXPECT_EQ(*space.value(text)->value.get_if<String>(), "Jello World");
  EXPECT_EQ(write1(matrix_var, AttributeId::Value, Variant(std::vector<std::int32_t>{0, 0}), "1,1:2"),
            StatusCode());
  auto m = space.value(matrix_var);
  EXPECT_EQ(*m->value.array_if<std::int32_t>(), (Array<std::int32_t>{1, 2, 3, 4, 0, 0}));
  EXPECT_EQ(m->value.array_dimensions(), (std::vector<std::int32_t>{2, 3}));
}

TEST_F(WriteServiceTest, CallbackDecides) {
  std::vector<std::int32_t> seen;
  ASSERT_TRUE(space
                  .set_value_callbacks(counter, nullptr,
                                       [&seen](const DataValue& v) {
                                         seen.push_back(*v.value.get_if<std::int32_t>());
                                         return seen.size() > 1 ? status::BadOutOfRange : StatusCode();
                                       })
                  .ok());
  EXPECT_EQ(write1(counter, AttributeId::Value, Variant(std::int32_t{1})), StatusCode());
  EXPECT_EQ(write1(counter, AttributeId::Value, Variant(std::int32_t{2})), status::BadOutOfRange);
  EXPECT_EQ(seen, (std::vector<std::int32_t>{1, 2}));
  EXPECT_EQ(*space.value(counter)->value.get_if<std::int32_t>(), 1);
}

TEST_F(WriteServiceTest, OtherAttributesFollowTheWriteMask) {
  const LocalizedText name({}, "Zähler");
  EXPECT_EQ(write1(counter, AttributeId::DisplayName, Variant(name)), status::BadNotWritable);
  auto* node = space.find_mutable(counter);
  node->write_mask = write_mask::DisplayName | write_mask::Description | write_mask::MinimumSamplingInterval;
  EXPECT_EQ(write1(counter, AttributeId::DisplayName, Variant(name)), status::BadUserAccessDenied);
  node->user_write_mask = node->write_mask;
  EXPECT_EQ(write1(counter, AttributeId::DisplayName, Variant(name)), StatusCode());
  EXPECT_EQ(space.find(counter)->display_name, name);
  EXPECT_EQ(write1(counter, AttributeId::DisplayName, Variant("plain string")), status::BadTypeMismatch);
  EXPECT_EQ(write1(counter, AttributeId::MinimumSamplingInterval, Variant(100.0)), StatusCode());
  EXPECT_EQ(space.find_as<VariableNode>(counter)->minimum_sampling_interval, 100.0);
  EXPECT_EQ(write1(counter, AttributeId::NodeId, Variant(counter)), status::BadNotWritable);
  EXPECT_EQ(write1(counter, AttributeId::Description, Variant(name), "0"), status::BadWriteNotSupported);
}

TEST_F(WriteServiceTest, ServiceLevelChecksAndNotifications) {
  WriteRequest request;
  EXPECT_EQ(write(space, request, ctx).response_header.service_result, status::BadNothingToDo);
  WriteValue item;
  item.node_id = counter;
  item.attribute_id = static_cast<std::uint32_t>(AttributeId::Value);
  item.value = DataValue(Variant(std::int32_t{3}));
  request.nodes_to_write = {item, item};
  ctx.limits.max_nodes_per_write = 1;
  EXPECT_EQ(write(space, request, ctx).response_header.service_result, status::BadTooManyOperations);
  ctx.limits.max_nodes_per_write = 0;
  int notified = 0;
  space.add_change_listener([&](const NodeChange& c) { notified += c.node_id == counter ? 1 : 0; });
  auto response = write(space, request, ctx);
  ASSERT_EQ(response.results.size(), 2U);
  EXPECT_EQ(response.results[1], StatusCode());
  EXPECT_EQ(notified, 2);
}

}  // namespace
}  // namespace sf::opcua::server::test
