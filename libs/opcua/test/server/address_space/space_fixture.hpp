// A namespace-0 address space with a small test model, and one-operation service helpers.
#pragma once

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "sf/core/clock.hpp"
#include "sf/opcua/server/address_space.hpp"
#include "sf/opcua/server/ns0.hpp"
#include "sf/opcua/server/services.hpp"
#include "sf/opcua/status_codes.hpp"

namespace sf::opcua::server::test {

inline NodeId ns0(std::uint32_t id) {
  return NodeId(0, id);
}

class SpaceFixture : public ::testing::Test {
 protected:
  void SetUp() override {
    auto built = build_namespace0(space);
    ASSERT_TRUE(built.ok()) << built.error().message;
    ctx.clock = &clock;
    ctx.continuations = &continuations;
    ns = space.add_namespace("urn:smartfactory:test");
    build_model();
  }

  // Objects/Demo (BaseObjectType) with variables and a method, all in namespace `ns`.
  void build_model() {
    ObjectSpec demo_spec;
    demo_spec.node_id = NodeId(ns, "Demo");
    demo_spec.browse_name = QualifiedName(ns, "Demo");
    demo_spec.parent = ns0(id::ObjectsFolder);
    demo_spec.reference_type = ns0(id::Organizes);
    demo = must(space.add_object(demo_spec));

    temperature = add_var("Temperature", ns0(id::Double), Variant(21.5), access_level::CurrentRead);
    counter = add_var("Counter", ns0(id::Int32), Variant(std::int32_t{7}), access_level::ReadWrite);
    doubles = add_var("Doubles", ns0(id::Double), Variant(std::vector<double>{1.0, 2.0, 3.0, 4.0, 5.0}),
                      access_level::ReadWrite, value_rank::OneDimension);
    text = add_var("Text", ns0(id::String), Variant("Hello World"), access_level::ReadWrite);
    auto matrix = Variant::matrix(Array<std::int32_t>{1, 2, 3, 4, 5, 6}, {2, 3});
    ASSERT_TRUE(matrix.ok());
    matrix_var = add_var("Matrix", ns0(id::Int32), *matrix, access_level::ReadWrite, 2);

    MethodSpec m;
    m.node_id = NodeId(ns, "Multiply");
    m.browse_name = QualifiedName(ns, "Multiply");
    m.parent = demo;
    m.input_arguments = {argument("a", id::Double), argument("b", id::Double)};
    m.output_arguments = {argument("product", id::Double)};
    m.callback = [](const NodeId&, const std::vector<Variant>& in, std::vector<Variant>& out) {
      out.emplace_back(*in[0].get_if<double>() * *in[1].get_if<double>());
      return StatusCode();
    };
    multiply = must(space.add_method(m));
  }

  static Argument argument(const std::string& name, std::uint32_t data_type,
                           std::int32_t rank = value_rank::Scalar) {
    Argument a;
    a.name = String(name);
    a.data_type = ns0(data_type);
    a.value_rank = rank;
    return a;
  }

  NodeId add_var(const std::string& name, const NodeId& data_type, const Variant& value, std::uint8_t access,
                 std::int32_t rank = value_rank::Scalar) {
    VariableSpec v;
    v.node_id = NodeId(ns, String(name));
    v.browse_name = QualifiedName(ns, String(name));
    v.parent = demo;
    v.data_type = data_type;
    v.value_rank = rank;
    v.value = DataValue(value);
    v.access_level = access;
    v.user_access_level = access;
    return must(space.add_variable(v));
  }

  template <typename T>
  static T must(Result<T> r) {
    EXPECT_TRUE(r.ok()) << (r.ok() ? "" : r.error().message);
    return r.ok() ? *std::move(r) : T{};
  }

  DataValue read1(const NodeId& node, AttributeId attribute, const String& range = String(),
                  TimestampsToReturn ts = TimestampsToReturn::Both) {
    ReadValueId item;
    item.node_id = node;
    item.attribute_id = static_cast<std::uint32_t>(attribute);
    item.index_range = range;
    return read_attribute(space, item, ts, ctx);
  }

  StatusCode write1(const NodeId& node, AttributeId attribute, const Variant& value,
                    const String& range = String()) {
    WriteValue item;
    item.node_id = node;
    item.attribute_id = static_cast<std::uint32_t>(attribute);
    item.index_range = range;
    item.value = DataValue(value);
    return write_attribute(space, item, ctx);
  }

  AddressSpace space;
  ManualClock clock;
  BrowseContinuations continuations{2};
  ServiceContext ctx;
  std::uint16_t ns = 0;
  NodeId demo, temperature, counter, doubles, text, matrix_var, multiply;
};

}  // namespace sf::opcua::server::test
