// The nodes of a server's address space (OPC 10000-3 §5): one class per NodeClass with the
// attributes of OPC 10000-3 §5.9 Table 7, and the references of a node, kept both ways (the
// forward reference on its source, the inverse one on its target; OPC 10000-3 §5.3.1).
//
// Nodes are plain data: the AddressSpace (address_space.hpp) owns them, keeps the references
// consistent and runs the value and method callbacks. Applications build nodes through the
// AddressSpace::add_* specs; NodeSet2 import builds them directly and passes them to
// AddressSpace::add_node.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <string_view>
#include <vector>

#include "sf/opcua/builtin_types.hpp"
#include "sf/opcua/node_ids.hpp"
#include "sf/opcua/status_code.hpp"
#include "sf/opcua/types.hpp"
#include "sf/opcua/variant.hpp"

namespace sf::opcua::server {

// Attribute ids (OPC 10000-6 Annex A.1), the attributeId of Read, Write and monitored items.
enum class AttributeId : std::uint32_t {
  NodeId = 1,
  NodeClass = 2,
  BrowseName = 3,
  DisplayName = 4,
  Description = 5,
  WriteMask = 6,
  UserWriteMask = 7,
  IsAbstract = 8,
  Symmetric = 9,
  InverseName = 10,
  ContainsNoLoops = 11,
  EventNotifier = 12,
  Value = 13,
  DataType = 14,
  ValueRank = 15,
  ArrayDimensions = 16,
  AccessLevel = 17,
  UserAccessLevel = 18,
  MinimumSamplingInterval = 19,
  Historizing = 20,
  Executable = 21,
  UserExecutable = 22,
  DataTypeDefinition = 23,
  RolePermissions = 24,
  UserRolePermissions = 25,
  AccessRestrictions = 26,
  AccessLevelEx = 27,
};
inline constexpr std::uint32_t kMaxAttributeId = 27;
// "Value", "BrowseName"; "AttributeId(<n>)" for an unknown id.
std::string_view attribute_name(AttributeId id);

// AccessLevelType bits (OPC 10000-3 §8.57); AccessLevelEx (§8.58) extends them to 32 bits.
namespace access_level {
inline constexpr std::uint8_t CurrentRead = 0x01;
inline constexpr std::uint8_t CurrentWrite = 0x02;
inline constexpr std::uint8_t HistoryRead = 0x04;
inline constexpr std::uint8_t HistoryWrite = 0x08;
inline constexpr std::uint8_t SemanticChange = 0x10;
inline constexpr std::uint8_t StatusWrite = 0x20;
inline constexpr std::uint8_t TimestampWrite = 0x40;
inline constexpr std::uint8_t ReadWrite = CurrentRead | CurrentWrite;
// AccessLevelExType bits above the AccessLevelType ones (OPC 10000-3 §8.58).
inline constexpr std::uint32_t NonatomicRead = 0x100;
inline constexpr std::uint32_t NonatomicWrite = 0x200;
inline constexpr std::uint32_t WriteFullArrayOnly = 0x400;
}  // namespace access_level

// AttributeWriteMask bits (OPC 10000-3 §8.60): which attributes other than Value a client may
// write (WriteMask) and the current user may write (UserWriteMask).
namespace write_mask {
inline constexpr std::uint32_t AccessLevel = 1U << 0U;
inline constexpr std::uint32_t ArrayDimensions = 1U << 1U;
inline constexpr std::uint32_t BrowseName = 1U << 2U;
inline constexpr std::uint32_t ContainsNoLoops = 1U << 3U;
inline constexpr std::uint32_t DataType = 1U << 4U;
inline constexpr std::uint32_t Description = 1U << 5U;
inline constexpr std::uint32_t DisplayName = 1U << 6U;
inline constexpr std::uint32_t EventNotifier = 1U << 7U;
inline constexpr std::uint32_t Executable = 1U << 8U;
inline constexpr std::uint32_t Historizing = 1U << 9U;
inline constexpr std::uint32_t InverseName = 1U << 10U;
inline constexpr std::uint32_t IsAbstract = 1U << 11U;
inline constexpr std::uint32_t MinimumSamplingInterval = 1U << 12U;
inline constexpr std::uint32_t NodeClass = 1U << 13U;
inline constexpr std::uint32_t NodeId = 1U << 14U;
inline constexpr std::uint32_t Symmetric = 1U << 15U;
inline constexpr std::uint32_t UserAccessLevel = 1U << 16U;
inline constexpr std::uint32_t UserExecutable = 1U << 17U;
inline constexpr std::uint32_t UserWriteMask = 1U << 18U;
inline constexpr std::uint32_t ValueRank = 1U << 19U;
inline constexpr std::uint32_t WriteMask = 1U << 20U;
inline constexpr std::uint32_t ValueForVariableType = 1U << 21U;
inline constexpr std::uint32_t DataTypeDefinition = 1U << 22U;
inline constexpr std::uint32_t RolePermissions = 1U << 23U;
inline constexpr std::uint32_t AccessRestrictions = 1U << 24U;
inline constexpr std::uint32_t AccessLevelEx = 1U << 25U;
}  // namespace write_mask

// EventNotifierType bits (OPC 10000-3 §8.59).
namespace event_notifier {
inline constexpr std::uint8_t None = 0x00;
inline constexpr std::uint8_t SubscribeToEvents = 0x01;
inline constexpr std::uint8_t HistoryRead = 0x04;
inline constexpr std::uint8_t HistoryWrite = 0x08;
}  // namespace event_notifier

// ValueRank values (OPC 10000-3 §5.6.2): n >= 1 is an array of n dimensions.
namespace value_rank {
inline constexpr std::int32_t ScalarOrOneDimension = -3;
inline constexpr std::int32_t Any = -2;
inline constexpr std::int32_t Scalar = -1;
inline constexpr std::int32_t OneOrMoreDimensions = 0;
inline constexpr std::int32_t OneDimension = 1;
}  // namespace value_rank

// A reference as stored on one of its two nodes: the other node and the direction as seen from
// this node (is_forward: this node is the source). Targets are local NodeIds.
struct Reference {
  NodeId reference_type_id;
  NodeId target_id;
  bool is_forward = true;

  friend bool operator==(const Reference&, const Reference&) = default;
};

// Value callbacks of a Variable (the "callback" value source). read replaces the stored value
// when set; it returns the whole value (IndexRange is applied afterwards) with its status and
// source timestamp. write is called for service writes and AddressSpace::set_value; it gets the
// complete new value (an IndexRange write is merged into the current value first) and its status
// is the result of the write. When write is set and returns Good, the stored value is updated
// too unless read is set.
using ValueReader = std::function<DataValue()>;
using ValueWriter = std::function<StatusCode(const DataValue& value)>;
// A Method's implementation (OPC 10000-4 §5.11.2): object is the objectId of the call; the input
// arguments are already checked against InputArguments; out is empty on entry. A Bad result is
// the CallMethodResult's statusCode; outputs are returned only for Good/Uncertain results.
using MethodCallback = std::function<StatusCode(const NodeId& object, const std::vector<Variant>& in,
                                                std::vector<Variant>& out)>;

// The attributes every node has (OPC 10000-3 §5.2) and its references.
struct Node {
  Node(const Node&) = delete;
  Node& operator=(const Node&) = delete;
  virtual ~Node() = default;

  NodeId node_id;
  QualifiedName browse_name;
  LocalizedText display_name;
  LocalizedText description;
  std::uint32_t write_mask = 0;
  std::uint32_t user_write_mask = 0;
  std::vector<Reference> references;

  [[nodiscard]] NodeClass node_class() const { return node_class_; }
  // The node as its concrete class, or nullptr: node.as<VariableNode>().
  template <typename T>
  [[nodiscard]] const T* as() const {
    return node_class_ == T::kNodeClass ? static_cast<const T*>(this) : nullptr;
  }
  template <typename T>
  [[nodiscard]] T* as() {
    return node_class_ == T::kNodeClass ? static_cast<T*>(this) : nullptr;
  }
  // A deep copy (callbacks are shared function objects).
  [[nodiscard]] virtual std::unique_ptr<Node> clone() const = 0;

  // The first target of a forward reference of exactly this type, or nullptr (e.g. the
  // HasTypeDefinition of an Object or Variable, the ModellingRule of an InstanceDeclaration).
  [[nodiscard]] const NodeId* forward_target(std::uint32_t ns0_reference_type) const;
  // The source of the first inverse reference of exactly this type (e.g. the HasSubtype parent).
  [[nodiscard]] const NodeId* inverse_target(std::uint32_t ns0_reference_type) const;

 protected:
  explicit Node(NodeClass node_class) : node_class_(node_class) {}
  void copy_base_to(Node& other) const;

 private:
  NodeClass node_class_;
};

// CRTP helper: kNodeClass, construction and clone() for each concrete class.
template <typename Derived, NodeClass kClass>
struct NodeOf : Node {
  static constexpr NodeClass kNodeClass = kClass;
  NodeOf() : Node(kClass) {}
  [[nodiscard]] std::unique_ptr<Node> clone() const override {
    auto copy = std::make_unique<Derived>();
    copy_base_to(*copy);
    static_cast<const Derived&>(*this).copy_attributes_to(*copy);
    return copy;
  }
};

// OPC 10000-3 §5.5.1
struct ObjectNode final : NodeOf<ObjectNode, NodeClass::Object> {
  std::uint8_t event_notifier = event_notifier::None;
  void copy_attributes_to(ObjectNode& o) const { o.event_notifier = event_notifier; }
};

// OPC 10000-3 §5.6.2. The value is the stored one unless `reader` is set.
struct VariableNode final : NodeOf<VariableNode, NodeClass::Variable> {
  DataValue value;
  ValueReader reader;
  ValueWriter writer;
  NodeId data_type = NodeId(0, id::BaseDataType);
  std::int32_t value_rank = value_rank::Scalar;
  std::vector<std::uint32_t> array_dimensions;
  std::uint8_t access_level = access_level::CurrentRead;
  std::uint8_t user_access_level = access_level::CurrentRead;
  // The AccessLevelEx bits above the AccessLevel byte (OPC 10000-3 §8.58); the attribute reads
  // as access_level | access_level_ex.
  std::uint32_t access_level_ex = 0;
  // Milliseconds; 0 = as fast as possible, -1 = indeterminate (OPC 10000-3 §5.6.2).
  double minimum_sampling_interval = -1.0;
  bool historizing = false;

  void copy_attributes_to(VariableNode& o) const;
};

// OPC 10000-3 §5.7
struct MethodNode final : NodeOf<MethodNode, NodeClass::Method> {
  bool executable = true;
  bool user_executable = true;
  MethodCallback callback;
  void copy_attributes_to(MethodNode& o) const {
    o.executable = executable;
    o.user_executable = user_executable;
    o.callback = callback;
  }
};

// OPC 10000-3 §5.5.2
struct ObjectTypeNode final : NodeOf<ObjectTypeNode, NodeClass::ObjectType> {
  bool is_abstract = false;
  void copy_attributes_to(ObjectTypeNode& o) const { o.is_abstract = is_abstract; }
};

// OPC 10000-3 §5.6.5. The Value is a default for instances (optional attribute: an empty
// Variant reads as a Null value).
struct VariableTypeNode final : NodeOf<VariableTypeNode, NodeClass::VariableType> {
  DataValue value;
  NodeId data_type = NodeId(0, id::BaseDataType);
  std::int32_t value_rank = value_rank::Any;
  std::vector<std::uint32_t> array_dimensions;
  bool is_abstract = false;
  void copy_attributes_to(VariableTypeNode& o) const {
    o.value = value;
    o.data_type = data_type;
    o.value_rank = value_rank;
    o.array_dimensions = array_dimensions;
    o.is_abstract = is_abstract;
  }
};

// OPC 10000-3 §5.3. inverse_name is null for symmetric and abstract types without one.
struct ReferenceTypeNode final : NodeOf<ReferenceTypeNode, NodeClass::ReferenceType> {
  bool is_abstract = false;
  bool symmetric = false;
  LocalizedText inverse_name;
  void copy_attributes_to(ReferenceTypeNode& o) const {
    o.is_abstract = is_abstract;
    o.symmetric = symmetric;
    o.inverse_name = inverse_name;
  }
};

// OPC 10000-3 §5.8.3. DataTypeDefinition is not stored (optional attribute).
struct DataTypeNode final : NodeOf<DataTypeNode, NodeClass::DataType> {
  bool is_abstract = false;
  void copy_attributes_to(DataTypeNode& o) const { o.is_abstract = is_abstract; }
};

// OPC 10000-3 §5.4
struct ViewNode final : NodeOf<ViewNode, NodeClass::View> {
  bool contains_no_loops = false;
  std::uint8_t event_notifier = event_notifier::None;
  void copy_attributes_to(ViewNode& o) const {
    o.contains_no_loops = contains_no_loops;
    o.event_notifier = event_notifier;
  }
};

// A new node of the given class (nullptr for Unspecified or an invalid class).
std::unique_ptr<Node> make_node(NodeClass node_class);

}  // namespace sf::opcua::server
