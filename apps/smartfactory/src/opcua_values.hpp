// Text and JSON forms of OPC UA values for the `opcua` commands: what a user types on the
// command line becomes a Variant of the node's DataType, and what the server returns is printed
// readably or as JSON.
#pragma once

#include <string>
#include <string_view>

#include <nlohmann/json.hpp>

#include "sf/core/result.hpp"
#include "sf/opcua/encoding.hpp"

namespace sf::app {

// The built-in type a DataType NodeId of namespace 0 stands for (Double for i=11, ...);
// Null for structures, enumerations (Int32 on the wire: mapped to Int32) and unknown types.
opcua::BuiltinType builtin_type_of_data_type(const opcua::NodeId& data_type);

// Parses `text` as a scalar of `type`, or as an array when it starts with '[' (JSON syntax,
// e.g. "[1, 2, 3]"). Booleans: true/false/1/0; DateTime: ISO 8601 UTC; NodeId: "ns=2;s=X".
Result<opcua::Variant> parse_variant(opcua::BuiltinType type, std::string_view text);

// "<BuiltinType>:<value>" (e.g. "Double:2.5", "Int32:[1,2]") or a bare value typed by `fallback`.
Result<opcua::Variant> parse_typed_variant(std::string_view text, opcua::BuiltinType fallback);

// A JSON value: numbers, booleans and strings as themselves, arrays as arrays, everything else
// as its text form.
nlohmann::json variant_to_json(const opcua::Variant& value);
nlohmann::json data_value_to_json(const opcua::DataValue& value);

// "ns=2;s=Demo" or "nsu=urn:x;s=Demo" (the namespace resolved by the caller) split into the
// optional URI and the rest as a NodeId in namespace 0.
struct NodeRef {
  std::string namespace_uri;  // empty unless "nsu=" was given
  opcua::NodeId node_id;
};
Result<NodeRef> parse_node_ref(std::string_view text);

}  // namespace sf::app
