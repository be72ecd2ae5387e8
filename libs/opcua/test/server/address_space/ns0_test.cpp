// The generated namespace 0: consistency of the whole graph, what generic clients browse first,
// and the live values of the Server object.
#include <set>
#include <unordered_set>

#include "sf/opcua/binary.hpp"
#include "space_fixture.hpp"

namespace sf::opcua::server::test {
namespace {

class Namespace0Test : public ::testing::Test {
 protected:
  void SetUp() override {
    auto built = build_namespace0(space);
    ASSERT_TRUE(built.ok()) << built.error().message;
    ctx.clock = &clock;
  }

  std::unordered_set<NodeId> forward_targets(const NodeId& node, std::uint32_t reference_type) {
    std::unordered_set<NodeId> out;
    for (const auto& r : space.find(node)->references) {
      if (r.is_forward && space.is_subtype(r.reference_type_id, ns0(reference_type))) {
        out.insert(r.target_id);
      }
    }
    return out;
  }

  DataValue read_value(std::uint32_t id) {
    ReadValueId item;
    item.node_id = ns0(id);
    item.attribute_id = static_cast<std::uint32_t>(AttributeId::Value);
    return read_attribute(space, item, TimestampsToReturn::Both, ctx);
  }

  AddressSpace space;
  ManualClock clock;
  ServiceContext ctx;
};

TEST_F(Namespace0Test, EveryReferenceTargetExistsAndTypesAreLinked) {
  EXPECT_EQ(space.size(), namespace0_node_count());
  EXPECT_GT(space.size(), 250U);
  const std::unordered_set<NodeId> roots = {ns0(id::BaseObjectType), ns0(id::BaseVariableType),
                                            ns0(id::BaseDataType), ns0(id::References)};
  std::size_t checked = 0;
  space.for_each_node([&](const Node& node) {
    ++checked;
    SCOPED_TRACE(to_string(node.node_id) + " " + to_string(node.browse_name));
    EXPECT_FALSE(node.browse_name.name.empty());
    for (const auto& r : node.references) {
      EXPECT_TRUE(space.contains(r.target_id)) << "dangling reference to " << to_string(r.target_id);
      EXPECT_NE(space.find_as<ReferenceTypeNode>(r.reference_type_id), nullptr);
      // The other half is there too.
      const Node* other = space.find(r.target_id);
      if (other != nullptr) {
        EXPECT_NE(std::find(other->references.begin(), other->references.end(),
                            Reference{r.reference_type_id, node.node_id, !r.is_forward}),
                  other->references.end());
      }
    }
    switch (node.node_class()) {
      case NodeClass::Object:
      case NodeClass::Variable: {
        const NodeId* type = node.forward_target(id::HasTypeDefinition);
        ASSERT_NE(type, nullptr) << "no HasTypeDefinition";
        const Node* type_node = space.find(*type);
        ASSERT_NE(type_node, nullptr);
        EXPECT_EQ(type_node->node_class(),
                  node.node_class() == NodeClass::Object ? NodeClass::ObjectType : NodeClass::VariableType);
        if (const auto* v = node.as<VariableNode>()) {
          EXPECT_NE(space.find_as<DataTypeNode>(v->data_type), nullptr) << "unknown DataType";
        }
        break;
      }
      case NodeClass::ObjectType:
      case NodeClass::VariableType:
      case NodeClass::DataType:
      case NodeClass::ReferenceType:
        if (!roots.contains(node.node_id)) {
          EXPECT_NE(node.inverse_target(id::HasSubtype), nullptr) << "no supertype";
        }
        break;
      default:
        break;
    }
  });
  EXPECT_EQ(checked, space.size());
}

TEST_F(Namespace0Test, BuildingTwiceIsRejected) {
  EXPECT_EQ(status_of(build_namespace0(space).error()), status::BadNodeIdExists);
}

TEST_F(Namespace0Test, BrowseFromRootReachesTheStandardFolders) {
  ServiceContext browse_ctx;
  BrowseRequest request;
  BrowseDescription d;
  d.node_id = ns0(id::RootFolder);
  d.browse_direction = BrowseDirection::Forward;
  d.reference_type_id = ns0(id::HierarchicalReferences);
  d.include_subtypes = true;
  d.result_mask = static_cast<std::uint32_t>(BrowseResultMask::All);
  request.nodes_to_browse.push_back(d);
  auto response = browse(space, request, browse_ctx);
  ASSERT_EQ(response.results.size(), 1U);
  std::set<std::string> names;
  for (const auto& r : response.results[0].references) {
    names.insert(r.browse_name.name.str());
    EXPECT_EQ(r.type_definition.node_id, ns0(id::FolderType));
  }
  EXPECT_EQ(names, (std::set<std::string>{"Objects", "Types", "Views"}));
  EXPECT_TRUE(forward_targets(ns0(id::ObjectsFolder), id::Organizes).contains(ns0(id::Server)));
  const auto types = forward_targets(ns0(id::TypesFolder), id::Organizes);
  for (auto folder :
       {id::ObjectTypesFolder, id::VariableTypesFolder, id::DataTypesFolder, id::ReferenceTypesFolder}) {
    EXPECT_TRUE(types.contains(ns0(folder)));
  }
  const auto server_children = forward_targets(ns0(id::Server), id::HierarchicalReferences);
  for (auto child :
       {id::Server_ServerArray, id::Server_NamespaceArray, id::Server_ServerStatus, id::Server_ServiceLevel,
        id::Server_ServerCapabilities, id::Server_ServerDiagnostics, id::Server_GetMonitoredItems}) {
    EXPECT_TRUE(server_children.contains(ns0(child))) << child;
  }
  EXPECT_EQ(space.find_as<ObjectNode>(ns0(id::Server))->event_notifier, event_notifier::SubscribeToEvents);
}

TEST_F(Namespace0Test, ReferenceTypesCarryTheirAttributes) {
  const auto* organizes = space.find_as<ReferenceTypeNode>(ns0(id::Organizes));
  ASSERT_NE(organizes, nullptr);
  EXPECT_EQ(organizes->inverse_name.text, "OrganizedBy");
  EXPECT_FALSE(organizes->is_abstract);
  EXPECT_TRUE(space.find_as<ReferenceTypeNode>(ns0(id::References))->symmetric);
  EXPECT_TRUE(space.find_as<ReferenceTypeNode>(ns0(id::HierarchicalReferences))->is_abstract);
  EXPECT_TRUE(space.is_subtype(ns0(id::HasNotifier), ns0(id::HasEventSource)));
  EXPECT_TRUE(space.is_subtype(ns0(id::GeneratesEvent), ns0(id::NonHierarchicalReferences)));
}

TEST_F(Namespace0Test, EventTypeAndEnumerationsDescribeThemselves) {
  for (const char* name :
       {"EventId", "EventType", "SourceNode", "SourceName", "Time", "ReceiveTime", "Message", "Severity"}) {
    const Node* p = space.child(ns0(id::BaseEventType), QualifiedName(0, name));
    ASSERT_NE(p, nullptr) << name;
    EXPECT_EQ(*p->forward_target(id::HasModellingRule), ns0(id::ModellingRule_Mandatory));
  }
  const Node* states = space.child(ns0(id::ServerState), QualifiedName(0, "EnumStrings"));
  ASSERT_NE(states, nullptr);
  const auto* strings = states->as<VariableNode>()->value.value.array_if<LocalizedText>();
  ASSERT_NE(strings, nullptr);
  ASSERT_EQ(strings->size(), 8U);
  EXPECT_EQ((*strings)[0].text, "Running");
  const Node* classes = space.child(ns0(id::NodeClass), QualifiedName(0, "EnumValues"));
  ASSERT_NE(classes, nullptr);
  const auto* values = classes->as<VariableNode>()->value.value.array_if<ExtensionObject>();
  ASSERT_NE(values, nullptr);
  ASSERT_EQ(values->size(), 9U);
  EXPECT_EQ((*values)[3].get_if<EnumValueType>()->value, 4);
  // Structures have their binary encoding, which maps back to the DataType.
  const NodeId* encoding = space.find(ns0(id::Argument))->forward_target(id::HasEncoding);
  ASSERT_NE(encoding, nullptr);
  EXPECT_EQ(*encoding, ns0(id::Argument_Encoding_DefaultBinary));
  EXPECT_EQ(space.find(*encoding)->browse_name, QualifiedName(0, "Default Binary"));
}

TEST_F(Namespace0Test, ServerObjectValuesAreLive) {
  ServerObjectInfo info;
  info.server_uris = {"urn:smartfactory:server"};
  info.build_info.product_name = String("smartfactory");
  info.build_info.software_version = String("0.1.0");
  info.clock = &clock;
  info.operation_limits.max_nodes_per_read = 500;
  ServerState state = ServerState::Running;
  info.state = [&state] { return state; };
  ASSERT_TRUE(install_server_object_callbacks(space, info).ok());
  space.add_namespace("urn:smartfactory:demo");

  const auto namespaces = read_value(id::Server_NamespaceArray);
  ASSERT_TRUE(namespaces.status.is_good());
  const auto* uris = namespaces.value.array_if<String>();
  ASSERT_NE(uris, nullptr);
  ASSERT_EQ(uris->size(), 2U);
  EXPECT_EQ((*uris)[1], "urn:smartfactory:demo");

  const auto t0 = read_value(id::Server_ServerStatus_CurrentTime);
  clock.advance(std::chrono::seconds(5));
  const auto t1 = read_value(id::Server_ServerStatus_CurrentTime);
  EXPECT_EQ(t1.value.get_if<DateTime>()->ticks() - t0.value.get_if<DateTime>()->ticks(),
            5 * DateTime::kTicksPerSecond);

  state = ServerState::Shutdown;
  const auto status = read_value(id::Server_ServerStatus);
  const auto* object = status.value.get_if<ExtensionObject>();
  ASSERT_NE(object, nullptr);
  const auto* s = object->get_if<ServerStatusDataType>();
  ASSERT_NE(s, nullptr);
  EXPECT_EQ(s->state, ServerState::Shutdown);
  EXPECT_EQ(s->build_info.product_name, "smartfactory");
  EXPECT_EQ(s->current_time, *t1.value.get_if<DateTime>());
  EXPECT_EQ(*read_value(id::Server_ServerStatus_State).value.get_if<std::int32_t>(),
            static_cast<std::int32_t>(ServerState::Shutdown));
  EXPECT_EQ(*read_value(id::Server_ServerStatus_BuildInfo_SoftwareVersion).value.get_if<String>(), "0.1.0");
  EXPECT_EQ(*read_value(id::Server_ServerCapabilities_OperationLimits_MaxNodesPerRead)
                 .value.get_if<std::uint32_t>(),
            500U);
  EXPECT_EQ(*read_value(id::Server_ServiceLevel).value.get_if<std::uint8_t>(), 255);
  EXPECT_EQ(*read_value(id::Server_ServerArray).value.array_if<String>(),
            Array<String>{"urn:smartfactory:server"});
}

TEST_F(Namespace0Test, GetMonitoredItemsDeclaresItsArguments) {
  const Node* input = space.child(ns0(id::Server_GetMonitoredItems), QualifiedName(0, "InputArguments"));
  ASSERT_NE(input, nullptr);
  const auto* args = input->as<VariableNode>()->value.value.array_if<ExtensionObject>();
  ASSERT_NE(args, nullptr);
  ASSERT_EQ(args->size(), 1U);
  EXPECT_EQ(args->front().get_if<Argument>()->name, "SubscriptionId");
  EXPECT_EQ(args->front().get_if<Argument>()->data_type, ns0(id::UInt32));
}

}  // namespace
}  // namespace sf::opcua::server::test
