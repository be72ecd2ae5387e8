// The server's address space (OPC 10000-3 §5, §8): the nodes, their references (stored both
// ways), the namespace table, and the API applications use to build their information model.
//
// Not thread-safe: the server guards it with its mutex, and value/method callbacks run under
// that lock (they must not call back into the server).
//
// A fresh AddressSpace is empty except for the namespace table ("http://opcfoundation.org/UA/"
// at index 0); build_namespace0 (ns0.hpp) adds the standard nodes the add_* helpers refer to
// (type definitions, reference types, the Objects folder).
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <unordered_map>
#include <vector>

#include "sf/core/result.hpp"
#include "sf/opcua/server/node.hpp"

namespace sf::opcua::server {

// What add_* needs for every node. node_id: the requested NodeId, or null for a fresh numeric
// one in the namespace of browse_name. parent + reference_type: the forward reference that
// links the node into the model (parent → node), e.g. Organizes from the Objects folder,
// HasComponent from an object, HasProperty for properties, HasSubtype from the supertype for
// types. A null parent adds no such reference. display_name defaults to browse_name.name.
struct NodeSpec {
  NodeId node_id;
  QualifiedName browse_name;
  LocalizedText display_name;
  LocalizedText description;
  NodeId parent;
  NodeId reference_type = NodeId(0, id::HasComponent);
  std::uint32_t write_mask = 0;
  // OPC 10000-3 §6.4.4: the ModellingRule of an InstanceDeclaration (children of types), e.g.
  // NodeId(0, id::ModellingRule_Mandatory); null for none.
  NodeId modelling_rule;
};

struct ObjectSpec : NodeSpec {
  NodeId type_definition = NodeId(0, id::BaseObjectType);
  std::uint8_t event_notifier = event_notifier::None;
  // Instantiates the type's InstanceDeclarations with ModellingRule Mandatory (recursively,
  // through the supertypes) as children of the new object (OPC 10000-3 §6.4.4.4).
  bool instantiate_mandatory = true;
};

struct VariableSpec : NodeSpec {
  NodeId type_definition = NodeId(0, id::BaseDataVariableType);
  NodeId data_type = NodeId(0, id::BaseDataType);
  std::int32_t value_rank = value_rank::Scalar;
  std::vector<std::uint32_t> array_dimensions;
  // The stored value (ignored for reading when `reader` is set).
  DataValue value;
  ValueReader reader;
  ValueWriter writer;
  std::uint8_t access_level = access_level::CurrentRead;
  std::uint8_t user_access_level = access_level::CurrentRead;
  double minimum_sampling_interval = -1.0;
  bool historizing = false;
  // As for ObjectSpec (e.g. the EURange property of an AnalogItemType variable).
  bool instantiate_mandatory = true;
};

// A Method with its InputArguments/OutputArguments properties (Argument[], OPC 10000-3 §5.7)
// created when the lists are not empty.
struct MethodSpec : NodeSpec {
  std::vector<Argument> input_arguments;
  std::vector<Argument> output_arguments;
  MethodCallback callback;
  bool executable = true;
};

// For the types the parent is the supertype and reference_type is HasSubtype by default.
struct ObjectTypeSpec : NodeSpec {
  ObjectTypeSpec() { reference_type = NodeId(0, id::HasSubtype); }
  bool is_abstract = false;
};

struct VariableTypeSpec : NodeSpec {
  VariableTypeSpec() { reference_type = NodeId(0, id::HasSubtype); }
  NodeId data_type = NodeId(0, id::BaseDataType);
  std::int32_t value_rank = value_rank::Any;
  std::vector<std::uint32_t> array_dimensions;
  DataValue value;
  bool is_abstract = false;
};

struct ReferenceTypeSpec : NodeSpec {
  ReferenceTypeSpec() { reference_type = NodeId(0, id::HasSubtype); }
  bool is_abstract = false;
  bool symmetric = false;
  LocalizedText inverse_name;
};

struct DataTypeSpec : NodeSpec {
  DataTypeSpec() { reference_type = NodeId(0, id::HasSubtype); }
  bool is_abstract = false;
};

// Views live under the Views folder (parent defaults to nothing: pass NodeId(0, id::ViewsFolder)
// with Organizes).
struct ViewSpec : NodeSpec {
  ViewSpec() { reference_type = NodeId(0, id::Organizes); }
  bool contains_no_loops = true;
  std::uint8_t event_notifier = event_notifier::None;
};

// A change observed by listeners (e.g. the subscriptions engine: data changes of values written
// through services or set_value, and nodes going away under a monitored item).
struct NodeChange {
  enum class Kind : std::uint8_t {
    AttributeWritten,
    NodeAdded,
    NodeDeleted,
    ReferenceAdded,
    ReferenceDeleted
  };
  Kind kind = Kind::AttributeWritten;
  NodeId node_id;
  AttributeId attribute = AttributeId::Value;  // for AttributeWritten
};
using ChangeListener = std::function<void(const NodeChange& change)>;

class AddressSpace {
 public:
  static constexpr std::string_view kNamespace0Uri = "http://opcfoundation.org/UA/";

  AddressSpace();
  AddressSpace(const AddressSpace&) = delete;
  AddressSpace& operator=(const AddressSpace&) = delete;
  AddressSpace(AddressSpace&&) noexcept;
  AddressSpace& operator=(AddressSpace&&) noexcept;
  ~AddressSpace();

  // ---- Namespaces (OPC 10000-5 §6.3.1 Server.NamespaceArray reads namespaces())
  // Idempotent: the index of uri, added at the end if new.
  std::uint16_t add_namespace(std::string_view uri);
  [[nodiscard]] std::optional<std::uint16_t> namespace_index(std::string_view uri) const;
  [[nodiscard]] const std::vector<std::string>& namespaces() const { return namespaces_; }

  // ---- Building the model. Each returns the new node's NodeId; errors (as status_error):
  // BadNodeIdExists, BadNodeIdInvalid (namespace not registered), BadParentNodeIdInvalid,
  // BadReferenceTypeIdInvalid, BadTypeDefinitionInvalid, BadBrowseNameInvalid (null name),
  // BadBrowseNameDuplicated (a child of the parent reached by a hierarchical reference other
  // than HasSubtype already has this browse name: browse paths must be unambiguous).
  Result<NodeId> add_object(const ObjectSpec& spec);
  Result<NodeId> add_variable(const VariableSpec& spec);
  Result<NodeId> add_method(const MethodSpec& spec);
  Result<NodeId> add_object_type(const ObjectTypeSpec& spec);
  Result<NodeId> add_variable_type(const VariableTypeSpec& spec);
  Result<NodeId> add_reference_type(const ReferenceTypeSpec& spec);
  Result<NodeId> add_data_type(const DataTypeSpec& spec);
  Result<NodeId> add_view(const ViewSpec& spec);
  // A property (HasProperty + PropertyType) under parent; value rank/array dims from the value.
  Result<NodeId> add_property(const NodeId& parent, const QualifiedName& browse_name, const Variant& value,
                              const NodeId& data_type, std::uint8_t access_level = access_level::CurrentRead);

  // Low level (namespace 0, NodeSet2 import): takes a fully built node as is, without any
  // reference; its `references` must be empty (use add_reference afterwards, once both ends
  // exist). A null node_id gets a fresh one in the namespace of its browse name.
  Result<NodeId> add_node(std::unique_ptr<Node> node);
  // Adds source --type--> target (forward) or source <--type-- target (forward=false: target is
  // the source of the forward reference). Both nodes and the (non-abstract or abstract)
  // reference type must exist: BadSourceNodeIdInvalid, BadTargetNodeIdInvalid,
  // BadReferenceTypeIdInvalid; an identical reference: BadDuplicateReferenceNotAllowed.
  Status add_reference(const NodeId& source, const NodeId& reference_type, const NodeId& target,
                       bool forward = true);
  // Removes the reference (both halves); BadNotFound when there is none.
  Status delete_reference(const NodeId& source, const NodeId& reference_type, const NodeId& target,
                          bool forward = true);
  // Removes the node, its own references and their other halves on other nodes
  // (delete_target_references=true, OPC 10000-4 §5.7.4.2) — with false the other halves stay
  // (dangling, as the spec allows). BadNodeIdUnknown when absent. Children are not deleted.
  Status delete_node(const NodeId& id, bool delete_target_references = true);

  // ---- Values (application side: no access-level checks)
  // The stored value of a Variable or VariableType; calls the writer of a Variable first (a Bad
  // status from it is returned as the error). Missing timestamps are left as they are.
  Status set_value(const NodeId& id, DataValue value);
  // The current value of a Variable (reader or stored) or VariableType.
  [[nodiscard]] Result<DataValue> value(const NodeId& id) const;
  // Installs/replaces the value callbacks of a Variable (BadNodeIdUnknown/BadNodeClassInvalid).
  Status set_value_callbacks(const NodeId& id, ValueReader reader, ValueWriter writer);
  // Installs/replaces the callback of a Method.
  Status set_method_callback(const NodeId& id, MethodCallback callback);

  // ---- Lookup
  [[nodiscard]] const Node* find(const NodeId& id) const;
  [[nodiscard]] Node* find_mutable(const NodeId& id);
  template <typename T>
  [[nodiscard]] const T* find_as(const NodeId& id) const {
    const Node* n = find(id);
    return n != nullptr ? n->as<T>() : nullptr;
  }
  template <typename T>
  [[nodiscard]] T* find_mutable_as(const NodeId& id) {
    Node* n = find_mutable(id);
    return n != nullptr ? n->as<T>() : nullptr;
  }
  [[nodiscard]] bool contains(const NodeId& id) const { return find(id) != nullptr; }
  [[nodiscard]] std::size_t size() const { return nodes_.size(); }
  // Every node, in no particular order (export, tests).
  void for_each_node(const std::function<void(const Node&)>& f) const;

  // True when type == base or type reaches base through inverse HasSubtype references
  // (OPC 10000-3 §7.10). Works for every type node class.
  [[nodiscard]] bool is_subtype(const NodeId& type, const NodeId& base) const;
  // Shorthand for NodeIds in namespace 0.
  [[nodiscard]] bool is_subtype(const NodeId& type, std::uint32_t ns0_base) const {
    return is_subtype(type, NodeId(0, ns0_base));
  }
  // The direct supertype (inverse HasSubtype), or nullptr.
  [[nodiscard]] const NodeId* supertype(const NodeId& type) const;
  // The HasTypeDefinition target of an Object or Variable, or nullptr.
  [[nodiscard]] const NodeId* type_definition(const NodeId& instance) const;
  // The child of parent reached by a forward hierarchical reference with this browse name, or
  // nullptr (first match).
  [[nodiscard]] const Node* child(const NodeId& parent, const QualifiedName& browse_name) const;
  // The reference type is HierarchicalReferences or a subtype of it.
  [[nodiscard]] bool is_hierarchical(const NodeId& reference_type) const;

  // ---- Change notifications (called synchronously after the change, under the server lock)
  std::size_t add_change_listener(ChangeListener listener);
  void remove_change_listener(std::size_t handle);
  // Service writes use this to report attribute changes (also called by set_value).
  void notify(const NodeChange& change) const;
  // Incremented on every structural change (node/reference added or removed).
  [[nodiscard]] std::uint64_t model_version() const { return model_version_; }

 private:
  Result<NodeId> insert(std::unique_ptr<Node> node, const NodeSpec& spec, const NodeId& type_definition);
  Status check_spec(const NodeSpec& spec) const;
  Result<NodeId> fresh_id(std::uint16_t ns);
  // OPC 10000-3 §6.4.4.4: copies of the Mandatory InstanceDeclarations of type (and its
  // supertypes) under instance, recursively; depth stops self-containing types.
  Status instantiate_children(const NodeId& instance, const NodeId& type, int depth = 0);
  // The mandatory children declared directly under source (a type or an InstanceDeclaration).
  Status instantiate_members(const NodeId& instance, const NodeId& source, int depth);
  Status instantiate_declaration(const NodeId& parent, const NodeId& reference_type, const Node& declaration,
                                 int depth);

  std::unordered_map<NodeId, std::unique_ptr<Node>> nodes_;
  std::vector<std::string> namespaces_;
  std::vector<std::uint32_t> next_numeric_id_;  // per namespace
  std::vector<std::pair<std::size_t, ChangeListener>> listeners_;
  std::size_t next_listener_ = 1;
  std::uint64_t model_version_ = 0;
};

}  // namespace sf::opcua::server
