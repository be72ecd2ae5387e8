// The Call service: object/method checks, executability, argument checks and outputs.
#include "space_fixture.hpp"

namespace sf::opcua::server::test {
namespace {

class CallServiceTest : public SpaceFixture {
 protected:
  CallMethodResult call1(const NodeId& object, const NodeId& method, std::vector<Variant> in) {
    CallRequest request;
    CallMethodRequest item;
    item.object_id = object;
    item.method_id = method;
    item.input_arguments = Array<Variant>(std::move(in));
    request.methods_to_call.push_back(item);
    auto response = call(space, request, ctx);
    EXPECT_EQ(response.results.size(), 1U);
    return response.results.empty() ? CallMethodResult{} : response.results[0];
  }
};

TEST_F(CallServiceTest, CallsTheMethod) {
  auto r = call1(demo, multiply, {Variant(3.0), Variant(4.0)});
  ASSERT_TRUE(r.status_code.is_good()) << to_string(r.status_code);
  ASSERT_EQ(r.output_arguments.size(), 1U);
  EXPECT_EQ(*r.output_arguments[0].get_if<double>(), 12.0);
  EXPECT_TRUE(r.input_argument_results.empty());
}

TEST_F(CallServiceTest, ArgumentErrors) {
  EXPECT_EQ(call1(demo, multiply, {Variant(3.0)}).status_code, status::BadArgumentsMissing);
  EXPECT_EQ(call1(demo, multiply, {Variant(3.0), Variant(4.0), Variant(5.0)}).status_code,
            status::BadTooManyArguments);
  auto wrong = call1(demo, multiply, {Variant(3.0), Variant("four")});
  EXPECT_EQ(wrong.status_code, status::BadInvalidArgument);
  ASSERT_EQ(wrong.input_argument_results.size(), 2U);
  EXPECT_EQ(wrong.input_argument_results[0], StatusCode());
  EXPECT_EQ(wrong.input_argument_results[1], status::BadTypeMismatch);
  EXPECT_TRUE(wrong.output_arguments.empty());
  auto array = call1(demo, multiply, {Variant(std::vector<double>{1.0}), Variant(2.0)});
  EXPECT_EQ(array.status_code, status::BadInvalidArgument);
}

TEST_F(CallServiceTest, ObjectAndMethodChecks) {
  EXPECT_EQ(call1(NodeId(ns, "nope"), multiply, {}).status_code, status::BadNodeIdUnknown);
  EXPECT_EQ(call1(counter, multiply, {}).status_code, status::BadNodeIdInvalid);
  EXPECT_EQ(call1(demo, NodeId(ns, "nope"), {}).status_code, status::BadMethodInvalid);
  EXPECT_EQ(call1(demo, counter, {}).status_code, status::BadMethodInvalid);
  // A method of another object.
  EXPECT_EQ(call1(ns0(id::Server), multiply, {}).status_code, status::BadMethodInvalid);
  space.find_mutable_as<MethodNode>(multiply)->executable = false;
  EXPECT_EQ(call1(demo, multiply, {Variant(1.0), Variant(2.0)}).status_code, status::BadNotExecutable);
  space.find_mutable_as<MethodNode>(multiply)->executable = true;
  struct NoCalls : UserContext {
    [[nodiscard]] bool can_call(const Node&) const override { return false; }
  } user;
  ctx.user = &user;
  EXPECT_EQ(call1(demo, multiply, {Variant(1.0), Variant(2.0)}).status_code, status::BadUserAccessDenied);
}

TEST_F(CallServiceTest, MethodsOfTheTypeServeItsInstances) {
  ObjectTypeSpec type_spec;
  type_spec.browse_name = QualifiedName(ns, "PumpType");
  type_spec.parent = ns0(id::BaseObjectType);
  const auto pump_type = must(space.add_object_type(type_spec));
  MethodSpec start;
  start.browse_name = QualifiedName(ns, "Start");
  start.parent = pump_type;
  NodeId called_on;
  start.callback = [&called_on](const NodeId& object, const std::vector<Variant>&, std::vector<Variant>&) {
    called_on = object;
    return StatusCode();
  };
  const auto start_id = must(space.add_method(start));
  ObjectSpec pump;
  pump.browse_name = QualifiedName(ns, "Pump1");
  pump.parent = demo;
  pump.type_definition = pump_type;
  const auto pump_id = must(space.add_object(pump));
  EXPECT_TRUE(call1(pump_id, start_id, {}).status_code.is_good());
  EXPECT_EQ(called_on, pump_id);

  // A method without an implementation.
  ASSERT_TRUE(space.set_method_callback(start_id, nullptr).ok());
  EXPECT_EQ(call1(pump_id, start_id, {}).status_code, status::BadNotImplemented);
}

TEST_F(CallServiceTest, CallbackStatusAndServiceChecks) {
  ASSERT_TRUE(
      space
          .set_method_callback(multiply,
                               [](const NodeId&, const std::vector<Variant>&, std::vector<Variant>& out) {
                                 out.emplace_back(1.0);
                                 return status::BadOutOfRange;
                               })
          .ok());
  auto r = call1(demo, multiply, {Variant(1.0), Variant(2.0)});
  EXPECT_EQ(r.status_code, status::BadOutOfRange);
  EXPECT_TRUE(r.output_arguments.empty());

  CallRequest request;
  EXPECT_EQ(call(space, request, ctx).response_header.service_result, status::BadNothingToDo);
  request.methods_to_call.resize(2);
  ctx.limits.max_nodes_per_method_call = 1;
  EXPECT_EQ(call(space, request, ctx).response_header.service_result, status::BadTooManyOperations);
}

}  // namespace
}  // namespace sf::opcua::server::test
