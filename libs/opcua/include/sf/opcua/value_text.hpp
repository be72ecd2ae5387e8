// OPC UA values as text, for command lines and configuration: what a user types becomes a
// Variant of the wanted built-in type, and node references name their namespace by index or URI.
#pragma once

#include <string>
#include <string_view>

#include "sf/core/result.hpp"
#include "sf/opcua/encoding.hpp"

namespace sf::opcua {

// The built-in type a namespace-0 DataType NodeId is (Double for i=11, ...; OPC 10000-6 §5.1.2),
// Int32 for Enumeration; Null for anything else. Subtypes (Duration, UtcTime, ...) need the
// type hierarchy: server::builtin_type_of.
BuiltinType builtin_type_of_ns0(const NodeId& data_type);

// Parses `text` as a scalar of `type`, or as an array when it starts with '[' (JSON syntax,
// e.g. "[1, 2, 3]"). Booleans: true/false/1/0; DateTime: ISO 8601 UTC; NodeId: "ns=2;s=X";
// ByteString: hex; StatusCode: its name.
Result<Variant> parse_variant(BuiltinType type, std::string_view text);

// "<BuiltinType>:<value>" (e.g. "Double:2.5", "Int32:[1,2]") or a bare value typed by `fallback`.
Result<Variant> parse_typed_variant(std::string_view text, BuiltinType fallback);

// "ns=2;s=Demo" or "nsu=urn:x;s=Demo" (the namespace resolved by the caller) split into the
// optional URI and the rest as a NodeId in namespace 0.
struct NodeRef {
  std::string namespace_uri;  // empty unless "nsu=" was given
  NodeId node_id;
};
Result<NodeRef> parse_node_ref(std::string_view text);

}  // namespace sf::opcua
