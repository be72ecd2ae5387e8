// The built-in type behind a DataType (OPC 10000-3 §5.8.3, OPC 10000-6 §5.1.2).
#include <memory>

#include "sf/opcua/server/ns0.hpp"
#include "sf/opcua/status_codes.hpp"
#include "sf/opcua/value_text.hpp"

namespace sf::opcua::server {

namespace {

// A DataType hierarchy is a few levels deep; a loop of HasSubtype references ends here.
constexpr int kMaxDepth = 32;

// Supertypes whose subtypes are not values of that built-in type: a subtype of Structure is a
// structure of its own, one of BaseDataType is abstract (Number, Integer, ...).
bool is_open_base(const NodeId& type) {
  return type == NodeId(0, id::Structure) || type == NodeId(0, id::BaseDataType);
}

}  // namespace

BuiltinType builtin_type_of(const AddressSpace& space, const NodeId& data_type) {
  if (const BuiltinType builtin = builtin_type_of_ns0(data_type); builtin != BuiltinType::Null) {
    return builtin;
  }
  const NodeId* type = space.supertype(data_type);
  for (int depth = 0; type != nullptr && depth < kMaxDepth; ++depth) {
    if (is_open_base(*type)) {
      return BuiltinType::Null;
    }
    if (const BuiltinType builtin = builtin_type_of_ns0(*type); builtin != BuiltinType::Null) {
      return builtin;
    }
    type = space.supertype(*type);
  }
  return BuiltinType::Null;
}

BuiltinType builtin_type_of(const NodeId& data_type) {
  static const std::unique_ptr<const AddressSpace> ns0 = [] {
    auto space = std::make_unique<AddressSpace>();
    (void)build_namespace0(*space);
    return space;
  }();
  return builtin_type_of(*ns0, data_type);
}

}  // namespace sf::opcua::server
