#include "opcua/model_nodes.hpp"

#include "sf/opcua/node_ids.hpp"

namespace sf::factory {

opcua::server::VariableSpec variable_spec(const opcua::NodeId& id, opcua::QualifiedName browse_name,
                                          const opcua::NodeId& parent, std::uint32_t data_type,
                                          bool property) {
  namespace ua = sf::opcua;
  opcua::server::VariableSpec spec;
  spec.node_id = id;
  spec.browse_name = std::move(browse_name);
  spec.parent = parent;
  spec.reference_type = ns0(property ? ua::id::HasProperty : ua::id::HasComponent);
  spec.type_definition = ns0(property ? ua::id::PropertyType : ua::id::BaseDataVariableType);
  spec.data_type = ns0(data_type);
  spec.instantiate_mandatory = false;
  return spec;
}

void historize(opcua::server::VariableSpec& spec) {
  namespace al = opcua::server::access_level;
  spec.historizing = true;
  spec.access_level |= al::HistoryRead;
  spec.user_access_level |= al::HistoryRead;
}

}  // namespace sf::factory
