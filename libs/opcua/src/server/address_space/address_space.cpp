// The AddressSpace: node storage, namespace table, references kept both ways (OPC 10000-3 §5.3),
// type hierarchy queries (§7.10) and values set by the application.
#include "sf/opcua/server/address_space.hpp"

#include <algorithm>
#include <utility>

#include "server/address_space/service_util.hpp"
#include "sf/core/log.hpp"
#include "sf/opcua/status_codes.hpp"

namespace sf::opcua::server {

namespace {

// Fresh numeric ids start here in namespace 0 so that they never meet the standard ones.
constexpr std::uint32_t kFirstFreeNs0Id = 1'000'000;
// Type hierarchies deeper than this are treated as cycles.
constexpr int kMaxTypeDepth = 64;

using detail::ns0;

Error rejected(StatusCode code, const std::string& what) {
  sf::log::get("opcua")->debug("address space: {}: {}", to_string(code), what);
  return status_error(code, what);
}

}  // namespace

AddressSpace::AddressSpace() : namespaces_{std::string(kNamespace0Uri)}, next_numeric_id_{kFirstFreeNs0Id} {}
AddressSpace::AddressSpace(AddressSpace&&) noexcept = default;
AddressSpace& AddressSpace::operator=(AddressSpace&&) noexcept = default;
AddressSpace::~AddressSpace() = default;

// ---- Namespaces

std::uint16_t AddressSpace::add_namespace(std::string_view uri) {
  if (auto index = namespace_index(uri)) {
    return *index;
  }
  namespaces_.emplace_back(uri);
  next_numeric_id_.push_back(1);
  ++model_version_;
  return static_cast<std::uint16_t>(namespaces_.size() - 1);
}

std::optional<std::uint16_t> AddressSpace::namespace_index(std::string_view uri) const {
  for (std::size_t i = 0; i < namespaces_.size(); ++i) {
    if (namespaces_[i] == uri) {
      return static_cast<std::uint16_t>(i);
    }
  }
  return std::nullopt;
}

Result<NodeId> AddressSpace::fresh_id(std::uint16_t ns) {
  if (ns >= namespaces_.size()) {
    return rejected(status::BadNodeIdInvalid, "namespace index " + std::to_string(ns) + " is not registered");
  }
  auto& next = next_numeric_id_[ns];
  while (nodes_.contains(NodeId(ns, next))) {
    ++next;
  }
  return NodeId(ns, next++);
}

// ---- Building the model

Status AddressSpace::check_spec(const NodeSpec& spec) const {
  if (spec.browse_name.name.empty()) {
    return rejected(status::BadBrowseNameInvalid, "a node needs a browse name");
  }
  if (!spec.node_id.is_null()) {
    if (spec.node_id.namespace_index >= namespaces_.size()) {
      return rejected(status::BadNodeIdInvalid, to_string(spec.node_id) + ": namespace is not registered");
    }
    if (contains(spec.node_id)) {
      return rejected(status::BadNodeIdExists, to_string(spec.node_id) + " exists");
    }
  }
  if (spec.parent.is_null()) {
    return {};
  }
  if (!contains(spec.parent)) {
    return rejected(status::BadParentNodeIdInvalid, "parent " + to_string(spec.parent) + " does not exist");
  }
  if (find_as<ReferenceTypeNode>(spec.reference_type) == nullptr) {
    return rejected(status::BadReferenceTypeIdInvalid,
                    to_string(spec.reference_type) + " is no ReferenceType");
  }
  if (spec.reference_type != ns0(id::HasSubtype) && is_hierarchical(spec.reference_type) &&
      child(spec.parent, spec.browse_name) != nullptr) {
    return rejected(status::BadBrowseNameDuplicated,
                    to_string(spec.parent) + " already has a child " + to_string(spec.browse_name));
  }
  if (!spec.modelling_rule.is_null() && !contains(spec.modelling_rule)) {
    return rejected(status::BadInvalidArgument,
                    "modelling rule " + to_string(spec.modelling_rule) + " is unknown");
  }
  return {};
}

Result<NodeId> AddressSpace::insert(std::unique_ptr<Node> node, const NodeSpec& spec,
                                    const NodeId& type_definition) {
  SF_TRY(check_spec(spec));
  if (!type_definition.is_null()) {
    const Node* type = find(type_definition);
    const NodeClass wanted =
        node->node_class() == NodeClass::Object ? NodeClass::ObjectType : NodeClass::VariableType;
    if (type == nullptr || type->node_class() != wanted) {
      return rejected(status::BadTypeDefinitionInvalid,
                      to_string(type_definition) + " is no " + to_string(wanted));
    }
  }
  node->node_id = spec.node_id;
  node->browse_name = spec.browse_name;
  node->display_name =
      spec.display_name.text.is_null() ? LocalizedText({}, spec.browse_name.name) : spec.display_name;
  node->description = spec.description;
  node->write_mask = spec.write_mask;
  node->user_write_mask = spec.write_mask;
  auto added = add_node(std::move(node));
  if (!added) {
    return added;
  }
  const NodeId& id = *added;
  if (!spec.parent.is_null()) {
    SF_TRY(add_reference(spec.parent, spec.reference_type, id));
  }
  if (!type_definition.is_null()) {
    SF_TRY(add_reference(id, ns0(id::HasTypeDefinition), type_definition));
  }
  if (!spec.modelling_rule.is_null()) {
    SF_TRY(add_reference(id, ns0(id::HasModellingRule), spec.modelling_rule));
  }
  return added;
}

Result<NodeId> AddressSpace::add_object(const ObjectSpec& spec) {
  auto node = std::make_unique<ObjectNode>();
  node->event_notifier = spec.event_notifier;
  auto id = insert(std::move(node), spec, spec.type_definition);
  if (id && spec.instantiate_mandatory) {
    SF_TRY(instantiate_children(*id, spec.type_definition));
  }
  return id;
}

Result<NodeId> AddressSpace::add_variable(const VariableSpec& spec) {
  auto node = std::make_unique<VariableNode>();
  node->value = spec.value;
  node->reader = spec.reader;
  node->writer = spec.writer;
  node->data_type = spec.data_type;
  node->value_rank = spec.value_rank;
  node->array_dimensions = spec.array_dimensions;
  node->access_level = spec.access_level;
  node->user_access_level = spec.user_access_level;
  node->minimum_sampling_interval = spec.minimum_sampling_interval;
  node->historizing = spec.historizing;
  if (find_as<DataTypeNode>(spec.data_type) == nullptr) {
    return rejected(status::BadTypeMismatch, "data type " + to_string(spec.data_type) + " is no DataType");
  }
  auto id = insert(std::move(node), spec, spec.type_definition);
  if (id && spec.instantiate_mandatory) {
    SF_TRY(instantiate_children(*id, spec.type_definition));
  }
  return id;
}

Result<NodeId> AddressSpace::add_method(const MethodSpec& spec) {
  auto node = std::make_unique<MethodNode>();
  node->executable = spec.executable;
  node->user_executable = spec.executable;
  node->callback = spec.callback;
  auto id = insert(std::move(node), spec, NodeId());
  if (!id) {
    return id;
  }
  // OPC 10000-3 §5.7: the arguments are Argument[] properties of the Method.
  for (const auto* list : {&spec.input_arguments, &spec.output_arguments}) {
    if (list->empty()) {
      continue;
    }
    Array<ExtensionObject> arguments;
    for (const auto& a : *list) {
      arguments.push_back(ExtensionObject::make(a));
    }
    const bool input = list == &spec.input_arguments;
    auto property = add_property(*id, QualifiedName(0, input ? "InputArguments" : "OutputArguments"),
                                 Variant(std::move(arguments)), ns0(id::Argument));
    if (!property) {
      return property.error();
    }
  }
  return id;
}

Result<NodeId> AddressSpace::add_property(const NodeId& parent, const QualifiedName& browse_name,
                                          const Variant& value, const NodeId& data_type,
                                          std::uint8_t access) {
  VariableSpec spec;
  spec.node_id = NodeId();
  spec.browse_name = browse_name;
  spec.parent = parent;
  spec.reference_type = ns0(id::HasProperty);
  spec.type_definition = ns0(id::PropertyType);
  spec.data_type = data_type;
  spec.value = DataValue(value);
  spec.access_level = access;
  spec.user_access_level = access;
  if (value.is_matrix()) {
    spec.value_rank = static_cast<std::int32_t>(value.array_dimensions().size());
  } else if (value.is_array()) {
    spec.value_rank = value_rank::OneDimension;
    spec.array_dimensions = {static_cast<std::uint32_t>(value.array_length())};
  }
  // Properties live in the namespace of their parent (their browse name may be namespace 0).
  auto id = fresh_id(parent.namespace_index);
  if (!id) {
    return id;
  }
  spec.node_id = *id;
  return add_variable(spec);
}

Result<NodeId> AddressSpace::add_object_type(const ObjectTypeSpec& spec) {
  auto node = std::make_unique<ObjectTypeNode>();
  node->is_abstract = spec.is_abstract;
  return insert(std::move(node), spec, NodeId());
}

Result<NodeId> AddressSpace::add_variable_type(const VariableTypeSpec& spec) {
  auto node = std::make_unique<VariableTypeNode>();
  node->value = spec.value;
  node->data_type = spec.data_type;
  node->value_rank = spec.value_rank;
  node->array_dimensions = spec.array_dimensions;
  node->is_abstract = spec.is_abstract;
  return insert(std::move(node), spec, NodeId());
}

Result<NodeId> AddressSpace::add_reference_type(const ReferenceTypeSpec& spec) {
  auto node = std::make_unique<ReferenceTypeNode>();
  node->is_abstract = spec.is_abstract;
  node->symmetric = spec.symmetric;
  node->inverse_name = spec.inverse_name;
  return insert(std::move(node), spec, NodeId());
}

Result<NodeId> AddressSpace::add_data_type(const DataTypeSpec& spec) {
  auto node = std::make_unique<DataTypeNode>();
  node->is_abstract = spec.is_abstract;
  return insert(std::move(node), spec, NodeId());
}

Result<NodeId> AddressSpace::add_view(const ViewSpec& spec) {
  auto node = std::make_unique<ViewNode>();
  node->contains_no_loops = spec.contains_no_loops;
  node->event_notifier = spec.event_notifier;
  return insert(std::move(node), spec, NodeId());
}

Result<NodeId> AddressSpace::add_node(std::unique_ptr<Node> node) {
  if (node == nullptr || node->node_class() == NodeClass::Unspecified) {
    return rejected(status::BadNodeClassInvalid, "no node");
  }
  if (!node->references.empty()) {
    return rejected(status::BadInvalidArgument, "add_node takes a node without references");
  }
  if (node->node_id.is_null()) {
    auto id = fresh_id(node->browse_name.namespace_index);
    if (!id) {
      return id;
    }
    node->node_id = *id;
  }
  if (node->node_id.namespace_index >= namespaces_.size()) {
    return rejected(status::BadNodeIdInvalid, to_string(node->node_id) + ": namespace is not registered");
  }
  NodeId id = node->node_id;
  if (!nodes_.emplace(id, std::move(node)).second) {
    return rejected(status::BadNodeIdExists, to_string(id) + " exists");
  }
  ++model_version_;
  notify({NodeChange::Kind::NodeAdded, id, AttributeId::NodeId});
  return id;
}

// ---- References

Status AddressSpace::add_reference(const NodeId& source, const NodeId& reference_type, const NodeId& target,
                                   bool forward) {
  Node* from = find_mutable(forward ? source : target);
  Node* to = find_mutable(forward ? target : source);
  if (find_mutable(source) == nullptr) {
    return rejected(status::BadSourceNodeIdInvalid, to_string(source) + " does not exist");
  }
  if (find_mutable(target) == nullptr) {
    return rejected(status::BadTargetNodeIdInvalid, to_string(target) + " does not exist");
  }
  if (find_as<ReferenceTypeNode>(reference_type) == nullptr) {
    return rejected(status::BadReferenceTypeIdInvalid, to_string(reference_type) + " is no ReferenceType");
  }
  Reference forward_half{reference_type, to->node_id, true};
  if (std::find(from->references.begin(), from->references.end(), forward_half) != from->references.end()) {
    return rejected(status::BadDuplicateReferenceNotAllowed,
                    to_string(from->node_id) + " already references " + to_string(to->node_id));
  }
  from->references.push_back(std::move(forward_half));
  to->references.push_back(Reference{reference_type, from->node_id, false});
  ++model_version_;
  notify({NodeChange::Kind::ReferenceAdded, from->node_id, AttributeId::NodeId});
  return {};
}

Status AddressSpace::delete_reference(const NodeId& source, const NodeId& reference_type,
                                      const NodeId& target, bool forward) {
  const NodeId& from_id = forward ? source : target;
  const NodeId& to_id = forward ? target : source;
  Node* from = find_mutable(from_id);
  Node* to = find_mutable(to_id);
  bool removed = false;
  if (from != nullptr) {
    removed = std::erase(from->references, Reference{reference_type, to_id, true}) > 0;
  }
  if (to != nullptr) {
    removed = std::erase(to->references, Reference{reference_type, from_id, false}) > 0 || removed;
  }
  if (!removed) {
    return rejected(status::BadNotFound, "no such reference from " + to_string(from_id));
  }
  ++model_version_;
  notify({NodeChange::Kind::ReferenceDeleted, from_id, AttributeId::NodeId});
  return {};
}

Status AddressSpace::delete_node(const NodeId& id, bool delete_target_references) {
  auto it = nodes_.find(id);
  if (it == nodes_.end()) {
    return rejected(status::BadNodeIdUnknown, to_string(id) + " does not exist");
  }
  std::unique_ptr<Node> node = std::move(it->second);
  nodes_.erase(it);
  if (delete_target_references) {
    for (const auto& r : node->references) {
      if (Node* other = find_mutable(r.target_id)) {
        std::erase(other->references, Reference{r.reference_type_id, id, !r.is_forward});
      }
    }
  }
  ++model_version_;
  notify({NodeChange::Kind::NodeDeleted, id, AttributeId::NodeId});
  return {};
}

// ---- Values

Status AddressSpace::set_value(const NodeId& id, DataValue value) {
  Node* node = find_mutable(id);
  if (node == nullptr) {
    return rejected(status::BadNodeIdUnknown, to_string(id) + " does not exist");
  }
  if (auto* variable = node->as<VariableNode>()) {
    if (variable->writer) {
      const StatusCode result = variable->writer(value);
      if (result.is_bad()) {
        return rejected(result, "the write callback of " + to_string(id) + " refused the value");
      }
    }
    variable->value = std::move(value);
  } else if (auto* type = node->as<VariableTypeNode>()) {
    type->value = std::move(value);
  } else {
    return rejected(status::BadNodeClassInvalid, to_string(id) + " has no Value");
  }
  notify({NodeChange::Kind::AttributeWritten, id, AttributeId::Value});
  return {};
}

Result<DataValue> AddressSpace::value(const NodeId& id) const {
  const Node* node = find(id);
  if (node == nullptr) {
    return status_error(status::BadNodeIdUnknown, to_string(id) + " does not exist");
  }
  if (const auto* variable = node->as<VariableNode>()) {
    return variable->reader ? variable->reader() : variable->value;
  }
  if (const auto* type = node->as<VariableTypeNode>()) {
    return type->value;
  }
  return status_error(status::BadAttributeIdInvalid, to_string(id) + " has no Value");
}

Status AddressSpace::set_value_callbacks(const NodeId& id, ValueReader reader, ValueWriter writer) {
  Node* node = find_mutable(id);
  if (node == nullptr) {
    return rejected(status::BadNodeIdUnknown, to_string(id) + " does not exist");
  }
  auto* variable = node->as<VariableNode>();
  if (variable == nullptr) {
    return rejected(status::BadNodeClassInvalid, to_string(id) + " is no Variable");
  }
  variable->reader = std::move(reader);
  variable->writer = std::move(writer);
  return {};
}

Status AddressSpace::set_method_callback(const NodeId& id, MethodCallback callback) {
  Node* node = find_mutable(id);
  if (node == nullptr) {
    return rejected(status::BadNodeIdUnknown, to_string(id) + " does not exist");
  }
  auto* method = node->as<MethodNode>();
  if (method == nullptr) {
    return rejected(status::BadNodeClassInvalid, to_string(id) + " is no Method");
  }
  method->callback = std::move(callback);
  return {};
}

// ---- Lookup

const Node* AddressSpace::find(const NodeId& id) const {
  auto it = nodes_.find(id);
  return it != nodes_.end() ? it->second.get() : nullptr;
}

Node* AddressSpace::find_mutable(const NodeId& id) {
  auto it = nodes_.find(id);
  return it != nodes_.end() ? it->second.get() : nullptr;
}

void AddressSpace::for_each_node(const std::function<void(const Node&)>& f) const {
  for (const auto& [id, node] : nodes_) {
    f(*node);
  }
}

const NodeId* AddressSpace::supertype(const NodeId& type) const {
  const Node* node = find(type);
  return node != nullptr ? node->inverse_target(id::HasSubtype) : nullptr;
}

bool AddressSpace::is_subtype(const NodeId& type, const NodeId& base) const {
  const NodeId* current = &type;
  for (int depth = 0; current != nullptr && depth < kMaxTypeDepth; ++depth) {
    if (*current == base) {
      return true;
    }
    current = supertype(*current);
  }
  return false;
}

const NodeId* AddressSpace::type_definition(const NodeId& instance) const {
  const Node* node = find(instance);
  return node != nullptr ? node->forward_target(id::HasTypeDefinition) : nullptr;
}

bool AddressSpace::is_hierarchical(const NodeId& reference_type) const {
  return is_subtype(reference_type, ns0(id::HierarchicalReferences));
}

const Node* AddressSpace::child(const NodeId& parent, const QualifiedName& browse_name) const {
  const Node* node = find(parent);
  if (node == nullptr) {
    return nullptr;
  }
  for (const auto& r : node->references) {
    if (!r.is_forward || r.reference_type_id == ns0(id::HasSubtype) ||
        !is_hierarchical(r.reference_type_id)) {
      continue;
    }
    const Node* target = find(r.target_id);
    if (target != nullptr && target->browse_name == browse_name) {
      return target;
    }
  }
  return nullptr;
}

// ---- Change notifications

std::size_t AddressSpace::add_change_listener(ChangeListener listener) {
  listeners_.emplace_back(next_listener_, std::move(listener));
  return next_listener_++;
}

void AddressSpace::remove_change_listener(std::size_t handle) {
  std::erase_if(listeners_, [handle](const auto& entry) { return entry.first == handle; });
}

void AddressSpace::notify(const NodeChange& change) const {
  for (const auto& [handle, listener] : listeners_) {
    listener(change);
  }
}

}  // namespace sf::opcua::server
