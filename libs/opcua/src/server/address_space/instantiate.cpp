// Instantiation of an ObjectType's or VariableType's mandatory children (OPC 10000-3 §6.4.4.4):
// every InstanceDeclaration with ModellingRule Mandatory, of the type and of its supertypes,
// becomes a node under the new instance with the same BrowseName, attributes and type
// definition. The most derived declaration of a BrowseName wins (§6.3.3.3).
#include <vector>

#include "sf/opcua/server/address_space.hpp"
#include "sf/opcua/status_codes.hpp"

namespace sf::opcua::server {

namespace {

constexpr int kMaxInstantiationDepth = 16;
constexpr int kMaxSupertypes = 64;

bool is_mandatory(const Node& declaration) {
  const NodeId* rule = declaration.forward_target(id::HasModellingRule);
  return rule != nullptr && *rule == NodeId(0, id::ModellingRule_Mandatory);
}

}  // namespace

Status AddressSpace::instantiate_children(const NodeId& instance, const NodeId& type, int depth) {
  const NodeId* current = &type;
  for (int level = 0; current != nullptr && level < kMaxSupertypes; ++level) {
    SF_TRY(instantiate_members(instance, *current, depth));
    current = supertype(*current);
  }
  return {};
}

Status AddressSpace::instantiate_members(const NodeId& instance, const NodeId& source, int depth) {
  if (depth > kMaxInstantiationDepth) {
    return status_error(status::BadInvalidArgument,
                        "instance declarations nest too deep under " + to_string(source));
  }
  const Node* source_node = find(source);
  if (source_node == nullptr) {
    return {};
  }
  // A copy: adding references below may grow the vectors of the nodes involved.
  const std::vector<Reference> references = source_node->references;
  for (const auto& r : references) {
    if (!r.is_forward || r.reference_type_id == NodeId(0, id::HasSubtype) ||
        !is_hierarchical(r.reference_type_id)) {
      continue;
    }
    const Node* declaration = find(r.target_id);
    if (declaration == nullptr || !is_mandatory(*declaration) ||
        child(instance, declaration->browse_name) != nullptr) {
      continue;
    }
    SF_TRY(instantiate_declaration(instance, r.reference_type_id, *declaration, depth + 1));
  }
  return {};
}

Status AddressSpace::instantiate_declaration(const NodeId& parent, const NodeId& reference_type,
                                             const Node& declaration, int depth) {
  std::unique_ptr<Node> copy = declaration.clone();
  copy->references.clear();
  auto fresh = fresh_id(parent.namespace_index);
  if (!fresh) {
    return fresh.error();
  }
  copy->node_id = *fresh;
  auto id = add_node(std::move(copy));
  if (!id) {
    return id.error();
  }
  SF_TRY(add_reference(parent, reference_type, *id));
  const NodeId* type = declaration.forward_target(id::HasTypeDefinition);
  if (type != nullptr) {
    SF_TRY(add_reference(*id, NodeId(0, id::HasTypeDefinition), *type));
  }
  // The declaration's own mandatory children first, then those its type definition adds.
  SF_TRY(instantiate_members(*id, declaration.node_id, depth));
  if (type != nullptr) {
    SF_TRY(instantiate_children(*id, *type, depth));
  }
  return {};
}

}  // namespace sf::opcua::server
