// What the XML codec needs to know of the C++ types behind OPC UA values: which built-in type an
// element name stands for, which structures it can decode from an ExtensionObject body, and the
// element name of each type (OPC 10000-6 §5.3.1: the element is named after the type).
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <tuple>
#include <type_traits>
#include <utility>

#include "sf/opcua/types.hpp"
#include "sf/opcua/variant.hpp"

namespace sf::opcua::server::nodeset {

template <typename T>
struct Tag {
  using type = T;
};

template <typename T>
concept Structure = requires {
  T::kTypeName;
}
&&requires(T& v) {
  visit_fields(v, [](std::string_view, auto&) {});
};

// The structures NodeSet2 files carry as Variable values (OPC 10000-3 §8.6 Argument, §8.40
// EnumValueType; OPC 10000-8 §5.6.3 EUInformation, §5.6.2 Range; OPC 10000-5 §12.4, §12.10).
using XmlStructures =
    std::tuple<Argument, EnumValueType, EUInformation, Range, BuildInfo, ServerStatusDataType>;

template <typename F, typename... T>
bool any_of_types(F&& f, std::tuple<T...>* /*types*/) {
  return (f(Tag<T>{}) || ...);
}
// Calls f(Tag<T>{}) for each of XmlStructures until it returns true; true if one did.
template <typename F>
bool any_xml_structure(F&& f) {
  return any_of_types(f, static_cast<XmlStructures*>(nullptr));
}

// Calls f(Tag<T>{}) with the C++ type of a built-in type id (Null: nothing is called and
// false is returned).
template <typename F>
bool with_builtin(BuiltinType type, F&& f) {
  switch (type) {
    case BuiltinType::Boolean:
      f(Tag<bool>{});
      break;
    case BuiltinType::SByte:
      f(Tag<std::int8_t>{});
      break;
    case BuiltinType::Byte:
      f(Tag<std::uint8_t>{});
      break;
    case BuiltinType::Int16:
      f(Tag<std::int16_t>{});
      break;
    case BuiltinType::UInt16:
      f(Tag<std::uint16_t>{});
      break;
    case BuiltinType::Int32:
      f(Tag<std::int32_t>{});
      break;
    case BuiltinType::UInt32:
      f(Tag<std::uint32_t>{});
      break;
    case BuiltinType::Int64:
      f(Tag<std::int64_t>{});
      break;
    case BuiltinType::UInt64:
      f(Tag<std::uint64_t>{});
      break;
    case BuiltinType::Float:
      f(Tag<float>{});
      break;
    case BuiltinType::Double:
      f(Tag<double>{});
      break;
    case BuiltinType::String:
      f(Tag<String>{});
      break;
    case BuiltinType::DateTime:
      f(Tag<DateTime>{});
      break;
    case BuiltinType::Guid:
      f(Tag<Guid>{});
      break;
    case BuiltinType::ByteString:
      f(Tag<ByteString>{});
      break;
    case BuiltinType::XmlElement:
      f(Tag<XmlElement>{});
      break;
    case BuiltinType::NodeId:
      f(Tag<NodeId>{});
      break;
    case BuiltinType::ExpandedNodeId:
      f(Tag<ExpandedNodeId>{});
      break;
    case BuiltinType::StatusCode:
      f(Tag<StatusCode>{});
      break;
    case BuiltinType::QualifiedName:
      f(Tag<QualifiedName>{});
      break;
    case BuiltinType::LocalizedText:
      f(Tag<LocalizedText>{});
      break;
    case BuiltinType::ExtensionObject:
      f(Tag<ExtensionObject>{});
      break;
    case BuiltinType::DataValue:
      f(Tag<DataValue>{});
      break;
    case BuiltinType::Variant:
      f(Tag<Variant>{});
      break;
    case BuiltinType::DiagnosticInfo:
      f(Tag<DiagnosticInfo>{});
      break;
    default:
      return false;
  }
  return true;
}

// The built-in type an element name stands for ("Double" → Double); Null when none.
BuiltinType builtin_by_name(std::string_view name);

// The element name of a value of type T: the built-in type's name, the structure's name, or
// Int32 for enumerations inside arrays (OPC 10000-6 §5.3.4 encodes their values as strings).
template <typename T>
std::string_view element_name() {
  if constexpr (Structure<T>) {
    return T::kTypeName;
  } else if constexpr (std::is_enum_v<T>) {
    return "Int32";
  } else if constexpr (std::is_same_v<T, Variant>) {
    return "Variant";
  } else {
    return to_string(Variant(T{}).type());
  }
}

// "dataType" → "DataType": XML element names of structure fields (OPC 10000-6 §5.3.6).
std::string field_element_name(std::string_view field);

}  // namespace sf::opcua::server::nodeset
