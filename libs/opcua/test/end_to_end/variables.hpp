// Variables the end-to-end tests put into a running server.
#pragma once

#include <functional>
#include <string>
#include <string_view>

#include "sf/opcua/server/server.hpp"

namespace sf::opcua::test {

// An Int32 variable `name` under Objects, in namespace `uri`, whose value `reader` gives.
inline NodeId add_int32_variable(server::Server& s, std::string_view uri, const std::string& name,
                                 std::function<DataValue()> reader) {
  NodeId node;
  s.with_address_space([&](server::AddressSpace& space) {
    const std::uint16_t ns = space.add_namespace(uri);
    server::VariableSpec spec;
    spec.node_id = NodeId(ns, String(name));
    spec.browse_name = QualifiedName(ns, name);
    spec.parent = NodeId(0, id::ObjectsFolder);
    spec.reference_type = NodeId(0, id::Organizes);
    spec.data_type = NodeId(0, id::Int32);
    spec.reader = std::move(reader);
    node = *space.add_variable(spec);
  });
  return node;
}

}  // namespace sf::opcua::test
