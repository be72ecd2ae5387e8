// The XML encoding of OPC 10000-6 §5.3 for the values of NodeSet2 files: the built-in types,
// the structures that appear as Variable values (Argument, EnumValueType, EUInformation, Range,
// BuildInfo, ServerStatusDataType) inside ExtensionObjects, arrays (ListOf<Type>) and matrices.
//
// Elements are read by local name (any prefix for http://opcfoundation.org/UA/2008/02/Types.xsd)
// and written with the prefix "uax", which the NodeSet2 root declares. NamespaceIndexes inside
// values (NodeId, ExpandedNodeId, QualifiedName) are translated through a NamespaceMap: a file
// numbers its namespaces in its own NamespaceUris table (OPC 10000-6 §F.2).
#pragma once

#include <pugixml.hpp>

#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "sf/core/result.hpp"
#include "sf/opcua/variant.hpp"

namespace sf::opcua::server::nodeset {

// Namespace indexes of one side mapped to the other: to[i] is the index of this side's
// namespace i on the other side. Index 0 (the OPC UA namespace) always maps to 0.
class NamespaceMap {
 public:
  NamespaceMap() = default;
  explicit NamespaceMap(std::vector<std::uint16_t> to) : to_(std::move(to)) {}
  [[nodiscard]] std::optional<std::uint16_t> map(std::uint16_t index) const;

 private:
  std::vector<std::uint16_t> to_;
};

// Where an element is ("file.xml:12:5"), for error messages.
using Locator = std::function<std::string(pugi::xml_node)>;

// Reads values. Errors (Errc::malformed) name the element's location and what was expected.
class XmlDecoder {
 public:
  XmlDecoder(const NamespaceMap& namespaces, Locator where) : ns_(namespaces), where_(std::move(where)) {}

  // The Variant held by a <Value> element: its first child element names the type
  // (<Double>, <ListOfString>, <ExtensionObject>, <Matrix> ...). An empty <Value/> is Null.
  Result<Variant> value(pugi::xml_node value_element);
  // A NodeId in text form with its namespace index translated.
  Result<NodeId> node_id(pugi::xml_node at, std::string_view text);
  // "2:Name" (or "Name" in namespace 0) with its namespace index translated.
  Result<QualifiedName> qualified_name(pugi::xml_node at, std::string_view text);

 private:
  const NamespaceMap& ns_;
  Locator where_;
  friend struct DecodeVisitor;
};

// Writes values; every namespace index must be mappable (the exporter lists each namespace a
// value uses in the file's NamespaceUris first).
class XmlEncoder {
 public:
  explicit XmlEncoder(const NamespaceMap& namespaces) : ns_(namespaces) {}

  // Appends the element(s) of `value` under the <Value> element (nothing for Null).
  void value(pugi::xml_node value_element, const Variant& value) const;
  [[nodiscard]] std::string node_id(const NodeId& id) const;
  [[nodiscard]] std::string qualified_name(const QualifiedName& name) const;

 private:
  const NamespaceMap& ns_;
  friend struct EncodeVisitor;
};

// The local name of an element, without its prefix.
std::string_view local_name(pugi::xml_node element);
// The first child element with this local name (any prefix), or an empty node.
pugi::xml_node child_element(pugi::xml_node parent, std::string_view name);

}  // namespace sf::opcua::server::nodeset
