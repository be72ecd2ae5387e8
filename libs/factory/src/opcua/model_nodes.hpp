// Node specs the factory's OPC UA models (machines, the order service) are built of.
#pragma once

#include <cstdint>

#include "sf/opcua/server/address_space.hpp"

namespace sf::factory {

// A node of namespace 0 (OPC 10000-5, 10000-6 NodeIds.csv).
inline opcua::NodeId ns0(std::uint32_t id) {
  return opcua::NodeId(0, id);
}

// A variable of a model: a data variable (HasComponent) or a property (HasProperty).
opcua::server::VariableSpec variable_spec(const opcua::NodeId& id, opcua::QualifiedName browse_name,
                                          const opcua::NodeId& parent, std::uint32_t data_type,
                                          bool property);

// A variable whose values the server keeps (Historizing, AccessLevel HistoryRead: OPC 10000-3
// §5.6.2, §8.57): what the cloud missed while it was away, it reads back with HistoryRead
// (OPC 10000-11 §6.4.3) from the server's MemoryHistory (settings_server).
void historize(opcua::server::VariableSpec& spec);

}  // namespace sf::factory
