// Nodes of the address space (OPC 10000-3 §5): attribute names, copies, reference lookups.
#include "sf/opcua/server/node.hpp"

#include <array>
#include <string>

namespace sf::opcua::server {

namespace {

// OPC 10000-6 Annex A.1, indexed by AttributeId.
constexpr std::array<std::string_view, kMaxAttributeId + 1> kAttributeNames = {
    "",
    "NodeId",
    "NodeClass",
    "BrowseName",
    "DisplayName",
    "Description",
    "WriteMask",
    "UserWriteMask",
    "IsAbstract",
    "Symmetric",
    "InverseName",
    "ContainsNoLoops",
    "EventNotifier",
    "Value",
    "DataType",
    "ValueRank",
    "ArrayDimensions",
    "AccessLevel",
    "UserAccessLevel",
    "MinimumSamplingInterval",
    "Historizing",
    "Executable",
    "UserExecutable",
    "DataTypeDefinition",
    "RolePermissions",
    "UserRolePermissions",
    "AccessRestrictions",
    "AccessLevelEx",
};

}  // namespace

std::string_view attribute_name(AttributeId id) {
  const auto index = static_cast<std::uint32_t>(id);
  if (index == 0 || index > kMaxAttributeId) {
    return "AttributeId(?)";
  }
  return kAttributeNames.at(index);
}

const NodeId* Node::forward_target(std::uint32_t ns0_reference_type) const {
  for (const auto& r : references) {
    if (r.is_forward && r.reference_type_id == NodeId(0, ns0_reference_type)) {
      return &r.target_id;
    }
  }
  return nullptr;
}

const NodeId* Node::inverse_target(std::uint32_t ns0_reference_type) const {
  for (const auto& r : references) {
    if (!r.is_forward && r.reference_type_id == NodeId(0, ns0_reference_type)) {
      return &r.target_id;
    }
  }
  return nullptr;
}

void Node::copy_base_to(Node& other) const {
  other.node_id = node_id;
  other.browse_name = browse_name;
  other.display_name = display_name;
  other.description = description;
  other.write_mask = write_mask;
  other.user_write_mask = user_write_mask;
  other.references = references;
}

void VariableNode::copy_attributes_to(VariableNode& o) const {
  o.value = value;
  o.reader = reader;
  o.writer = writer;
  o.data_type = data_type;
  o.value_rank = value_rank;
  o.array_dimensions = array_dimensions;
  o.access_level = access_level;
  o.user_access_level = user_access_level;
  o.access_level_ex = access_level_ex;
  o.minimum_sampling_interval = minimum_sampling_interval;
  o.historizing = historizing;
}

std::unique_ptr<Node> make_node(NodeClass node_class) {
  switch (node_class) {
    case NodeClass::Object:
      return std::make_unique<ObjectNode>();
    case NodeClass::Variable:
      return std::make_unique<VariableNode>();
    case NodeClass::Method:
      return std::make_unique<MethodNode>();
    case NodeClass::ObjectType:
      return std::make_unique<ObjectTypeNode>();
    case NodeClass::VariableType:
      return std::make_unique<VariableTypeNode>();
    case NodeClass::ReferenceType:
      return std::make_unique<ReferenceTypeNode>();
    case NodeClass::DataType:
      return std::make_unique<DataTypeNode>();
    case NodeClass::View:
      return std::make_unique<ViewNode>();
    case NodeClass::Unspecified:
      break;
  }
  return nullptr;
}

}  // namespace sf::opcua::server
