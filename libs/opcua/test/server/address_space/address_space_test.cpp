// The AddressSpace API: namespaces, add_*, references both ways, deletion, values and
// callbacks, type hierarchy queries, instantiation of mandatory children, change listeners.
#include <algorithm>

#include "space_fixture.hpp"

namespace sf::opcua::server::test {
namespace {

using AddressSpaceTest = SpaceFixture;

bool has_reference(const Node& node, const NodeId& type, const NodeId& target, bool forward) {
  return std::find(node.references.begin(), node.references.end(), Reference{type, target, forward}) !=
         node.references.end();
}

TEST_F(AddressSpaceTest, NamespacesAreIdempotentAndListed) {
  EXPECT_EQ(space.namespaces().front(), "http://opcfoundation.org/UA/");
  EXPECT_EQ(space.add_namespace("urn:smartfactory:test"), ns);
  const auto other = space.add_namespace("urn:other");
  EXPECT_EQ(other, ns + 1);
  EXPECT_EQ(space.namespace_index("urn:other"), other);
  EXPECT_FALSE(space.namespace_index("urn:unknown").has_value());
  EXPECT_EQ(space.namespaces().size(), std::size_t{other} + 1);
}

TEST_F(AddressSpaceTest, AddObjectStoresReferencesBothWays) {
  const Node* node = space.find(demo);
  ASSERT_NE(node, nullptr);
  EXPECT_EQ(node->node_class(), NodeClass::Object);
  EXPECT_EQ(node->display_name.text, "Demo");
  EXPECT_TRUE(has_reference(*node, ns0(id::Organizes), ns0(id::ObjectsFolder), false));
  EXPECT_TRUE(has_reference(*node, ns0(id::HasTypeDefinition), ns0(id::BaseObjectType), true));
  EXPECT_TRUE(has_reference(*space.find(ns0(id::ObjectsFolder)), ns0(id::Organizes), demo, true));
  EXPECT_TRUE(has_reference(*space.find(ns0(id::BaseObjectType)), ns0(id::HasTypeDefinition), demo, false));
  ASSERT_NE(space.type_definition(demo), nullptr);
  EXPECT_EQ(*space.type_definition(demo), ns0(id::BaseObjectType));
  EXPECT_EQ(space.child(ns0(id::ObjectsFolder), QualifiedName(ns, "Demo")), node);
}

TEST_F(AddressSpaceTest, FreshIdsAreNumericInTheBrowseNameNamespace) {
  ObjectSpec spec;
  spec.browse_name = QualifiedName(ns, "Fresh");
  spec.parent = demo;
  const auto a = must(space.add_object(spec));
  spec.browse_name = QualifiedName(ns, "Fresh2");
  const auto b = must(space.add_object(spec));
  EXPECT_EQ(a.namespace_index, ns);
  EXPECT_TRUE(a.is_numeric());
  EXPECT_NE(a, b);
}

TEST_F(AddressSpaceTest, AddRejectsBadSpecs) {
  ObjectSpec spec;
  spec.browse_name = QualifiedName(ns, "X");
  spec.node_id = demo;
  EXPECT_EQ(status_of(space.add_object(spec).error()), status::BadNodeIdExists);
  spec.node_id = NodeId(99, 1);
  EXPECT_EQ(status_of(space.add_object(spec).error()), status::BadNodeIdInvalid);
  spec.node_id = NodeId();
  spec.parent = NodeId(ns, "missing");
  EXPECT_EQ(status_of(space.add_object(spec).error()), status::BadParentNodeIdInvalid);
  spec.parent = demo;
  spec.reference_type = ns0(id::BaseObjectType);
  EXPECT_EQ(status_of(space.add_object(spec).error()), status::BadReferenceTypeIdInvalid);
  spec.reference_type = ns0(id::HasComponent);
  spec.type_definition = ns0(id::BaseDataVariableType);
  EXPECT_EQ(status_of(space.add_object(spec).error()), status::BadTypeDefinitionInvalid);
  spec.type_definition = ns0(id::BaseObjectType);
  spec.browse_name = QualifiedName(ns, "Temperature");
  EXPECT_EQ(status_of(space.add_object(spec).error()), status::BadBrowseNameDuplicated);
  spec.browse_name = QualifiedName();
  EXPECT_EQ(status_of(space.add_object(spec).error()), status::BadBrowseNameInvalid);
}

TEST_F(AddressSpaceTest, MethodGetsArgumentProperties) {
  const Node* input = space.child(multiply, QualifiedName(0, "InputArguments"));
  const Node* output = space.child(multiply, QualifiedName(0, "OutputArguments"));
  ASSERT_NE(input, nullptr);
  ASSERT_NE(output, nullptr);
  const auto* v = input->as<VariableNode>();
  ASSERT_NE(v, nullptr);
  EXPECT_EQ(v->data_type, ns0(id::Argument));
  EXPECT_EQ(v->value_rank, 1);
  EXPECT_EQ(v->array_dimensions, std::vector<std::uint32_t>{2});
  const auto* list = v->value.value.array_if<ExtensionObject>();
  ASSERT_NE(list, nullptr);
  ASSERT_EQ(list->size(), 2U);
  EXPECT_EQ((*list)[1].get_if<Argument>()->name, "b");
  EXPECT_EQ(*space.type_definition(input->node_id), ns0(id::PropertyType));
}

TEST_F(AddressSpaceTest, AddReferenceChecksEndsAndDuplicates) {
  EXPECT_TRUE(space.add_reference(demo, ns0(id::Organizes), temperature).ok());
  EXPECT_EQ(status_of(space.add_reference(demo, ns0(id::Organizes), temperature).error()),
            status::BadDuplicateReferenceNotAllowed);
  EXPECT_EQ(status_of(space.add_reference(NodeId(ns, "nope"), ns0(id::Organizes), demo).error()),
            status::BadSourceNodeIdInvalid);
  EXPECT_EQ(status_of(space.add_reference(demo, ns0(id::Organizes), NodeId(ns, "nope")).error()),
            status::BadTargetNodeIdInvalid);
  EXPECT_EQ(status_of(space.add_reference(demo, demo, temperature).error()),
            status::BadReferenceTypeIdInvalid);
  // An inverse reference: temperature is the source of the forward half.
  EXPECT_TRUE(space.add_reference(demo, ns0(id::HasEventSource), temperature, false).ok());
  EXPECT_TRUE(has_reference(*space.find(temperature), ns0(id::HasEventSource), demo, true));
  EXPECT_TRUE(space.delete_reference(demo, ns0(id::HasEventSource), temperature, false).ok());
  EXPECT_FALSE(has_reference(*space.find(temperature), ns0(id::HasEventSource), demo, true));
  EXPECT_EQ(status_of(space.delete_reference(demo, ns0(id::HasEventSource), temperature, false).error()),
            status::BadNotFound);
}

TEST_F(AddressSpaceTest, DeleteNodeRemovesTheOtherHalves) {
  ASSERT_TRUE(space.delete_node(temperature).ok());
  EXPECT_EQ(space.find(temperature), nullptr);
  EXPECT_FALSE(has_reference(*space.find(demo), ns0(id::HasComponent), temperature, true));
  EXPECT_EQ(status_of(space.delete_node(temperature).error()), status::BadNodeIdUnknown);
  ASSERT_TRUE(space.delete_node(counter, false).ok());
  EXPECT_TRUE(has_reference(*space.find(demo), ns0(id::HasComponent), counter, true));  // left dangling
}

TEST_F(AddressSpaceTest, SetValueAndCallbacks) {
  ASSERT_TRUE(space.set_value(temperature, DataValue(Variant(30.0))).ok());
  EXPECT_EQ(*space.value(temperature)->value.get_if<double>(), 30.0);

  int writes = 0;
  ASSERT_TRUE(space
                  .set_value_callbacks(
                      counter, [] { return DataValue(Variant(std::int32_t{42})); },
                      [&writes](const DataValue& v) {
                        ++writes;
                        return *v.value.get_if<std::int32_t>() < 0 ? status::BadOutOfRange : StatusCode();
                      })
                  .ok());
  EXPECT_EQ(*space.value(counter)->value.get_if<std::int32_t>(), 42);
  EXPECT_TRUE(space.set_value(counter, DataValue(Variant(std::int32_t{1}))).ok());
  EXPECT_EQ(status_of(space.set_value(counter, DataValue(Variant(std::int32_t{-1}))).error()),
            status::BadOutOfRange);
  EXPECT_EQ(writes, 2);
  EXPECT_EQ(status_of(space.set_value(demo, DataValue()).error()), status::BadNodeClassInvalid);
  EXPECT_EQ(status_of(space.value(NodeId(ns, "nope")).error()), status::BadNodeIdUnknown);
  EXPECT_EQ(status_of(space.set_value_callbacks(demo, nullptr, nullptr).error()),
            status::BadNodeClassInvalid);
  EXPECT_EQ(status_of(space.set_method_callback(demo, nullptr).error()), status::BadNodeClassInvalid);
}

TEST_F(AddressSpaceTest, TypeHierarchies) {
  EXPECT_TRUE(space.is_subtype(ns0(id::HasComponent), ns0(id::HasComponent)));
  EXPECT_TRUE(space.is_subtype(ns0(id::HasOrderedComponent), ns0(id::HierarchicalReferences)));
  EXPECT_TRUE(space.is_subtype(ns0(id::HasProperty), id::References));
  EXPECT_FALSE(space.is_subtype(ns0(id::HasTypeDefinition), ns0(id::HierarchicalReferences)));
  EXPECT_TRUE(space.is_subtype(ns0(id::Int32), ns0(id::Number)));
  EXPECT_TRUE(space.is_subtype(ns0(id::Duration), ns0(id::Double)));
  EXPECT_TRUE(space.is_subtype(ns0(id::ServerState), ns0(id::Enumeration)));
  EXPECT_TRUE(space.is_subtype(ns0(id::Argument), ns0(id::Structure)));
  EXPECT_FALSE(space.is_subtype(ns0(id::Double), ns0(id::Integer)));
  EXPECT_TRUE(space.is_subtype(ns0(id::FolderType), ns0(id::BaseObjectType)));
  EXPECT_TRUE(space.is_subtype(ns0(id::AnalogItemType), ns0(id::BaseDataVariableType)));
  EXPECT_TRUE(space.is_subtype(ns0(id::PropertyType), ns0(id::BaseVariableType)));
  EXPECT_FALSE(space.is_subtype(ns0(id::BaseObjectType), ns0(id::FolderType)));
  EXPECT_FALSE(space.is_subtype(NodeId(ns, "nope"), ns0(id::BaseObjectType)));
  EXPECT_TRUE(space.is_hierarchical(ns0(id::Organizes)));
  EXPECT_FALSE(space.is_hierarchical(ns0(id::HasEncoding)));
}

TEST_F(AddressSpaceTest, CustomTypesInstantiateMandatoryChildren) {
  ObjectTypeSpec type_spec;
  type_spec.node_id = NodeId(ns, "MotorType");
  type_spec.browse_name = QualifiedName(ns, "MotorType");
  type_spec.parent = ns0(id::BaseObjectType);
  const auto motor_type = must(space.add_object_type(type_spec));

  VariableSpec speed;
  speed.browse_name = QualifiedName(ns, "Speed");
  speed.parent = motor_type;
  speed.data_type = ns0(id::Double);
  speed.value = DataValue(Variant(0.0));
  speed.modelling_rule = ns0(id::ModellingRule_Mandatory);
  ASSERT_TRUE(space.add_variable(speed).ok());
  VariableSpec note = speed;
  note.browse_name = QualifiedName(ns, "Note");
  note.modelling_rule = ns0(id::ModellingRule_Optional);
  ASSERT_TRUE(space.add_variable(note).ok());

  ObjectSpec motor;
  motor.browse_name = QualifiedName(ns, "Motor1");
  motor.parent = ns0(id::ObjectsFolder);
  motor.reference_type = ns0(id::Organizes);
  motor.type_definition = motor_type;
  const auto m1 = must(space.add_object(motor));
  const Node* child = space.child(m1, QualifiedName(ns, "Speed"));
  ASSERT_NE(child, nullptr);
  EXPECT_NE(child->node_id, NodeId());
  EXPECT_EQ(child->node_class(), NodeClass::Variable);
  EXPECT_EQ(child->as<VariableNode>()->data_type, ns0(id::Double));
  EXPECT_EQ(*space.type_definition(child->node_id), ns0(id::BaseDataVariableType));
  EXPECT_EQ(child->forward_target(id::HasModellingRule), nullptr);
  EXPECT_EQ(space.child(m1, QualifiedName(ns, "Note")), nullptr);

  // A variable of AnalogItemType gets its mandatory EURange property (OPC 10000-8 §5.3.2.4).
  VariableSpec analog;
  analog.browse_name = QualifiedName(ns, "Pressure");
  analog.parent = demo;
  analog.type_definition = ns0(id::AnalogItemType);
  analog.data_type = ns0(id::Double);
  const auto pressure = must(space.add_variable(analog));
  const Node* eu_range = space.child(pressure, QualifiedName(0, "EURange"));
  ASSERT_NE(eu_range, nullptr);
  EXPECT_EQ(eu_range->as<VariableNode>()->data_type, ns0(id::Range));
  EXPECT_EQ(space.child(pressure, QualifiedName(0, "EngineeringUnits")), nullptr);  // optional
}

TEST_F(AddressSpaceTest, ListenersSeeChanges) {
  std::vector<NodeChange> seen;
  const auto handle = space.add_change_listener([&seen](const NodeChange& c) { seen.push_back(c); });
  ASSERT_TRUE(space.set_value(counter, DataValue(Variant(std::int32_t{3}))).ok());
  ASSERT_EQ(seen.size(), 1U);
  EXPECT_EQ(seen[0].kind, NodeChange::Kind::AttributeWritten);
  EXPECT_EQ(seen[0].node_id, counter);
  EXPECT_EQ(seen[0].attribute, AttributeId::Value);
  const auto version = space.model_version();
  ASSERT_TRUE(space.delete_node(text).ok());
  EXPECT_GT(space.model_version(), version);
  EXPECT_EQ(seen.back().kind, NodeChange::Kind::NodeDeleted);
  space.remove_change_listener(handle);
  const auto count = seen.size();
  ASSERT_TRUE(space.set_value(counter, DataValue(Variant(std::int32_t{4}))).ok());
  EXPECT_EQ(seen.size(), count);
}

TEST_F(AddressSpaceTest, AddNodeTakesPrebuiltNodes) {
  auto node = std::make_unique<ObjectNode>();
  node->node_id = NodeId(ns, "Imported");
  node->browse_name = QualifiedName(ns, "Imported");
  ASSERT_TRUE(space.add_node(std::move(node)).ok());
  auto with_refs = std::make_unique<ObjectNode>();
  with_refs->browse_name = QualifiedName(ns, "Refs");
  with_refs->references.push_back(Reference{ns0(id::Organizes), demo, false});
  EXPECT_EQ(status_of(space.add_node(std::move(with_refs)).error()), status::BadInvalidArgument);
  const Node* copy_source = space.find(temperature);
  auto copy = copy_source->clone();
  EXPECT_EQ(copy->as<VariableNode>()->value, copy_source->as<VariableNode>()->value);
  EXPECT_EQ(copy->references, copy_source->references);
}

}  // namespace
}  // namespace sf::opcua::server::test
