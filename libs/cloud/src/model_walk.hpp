// Finding what to collect on one server: the subscribe rules of cloud.yaml turned into the
// Variables they name, by browsing the server's information model (OPC 10000-4 §5.8).
#pragma once

#include <functional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "sf/cloud/config.hpp"
#include "sf/opcua/client/client.hpp"

namespace sf::cloud::detail {

// The server's NamespaceArray: NodeIds in text with the namespace named by URI ("nsu=URI;s=X"),
// so that series keys survive a server that renumbers its namespaces.
class NamespaceTable {
 public:
  static Result<NamespaceTable> read(opcua::SyncClient& client);
  explicit NamespaceTable(std::vector<std::string> uris) : uris_(std::move(uris)) {}

  // "ns=2;s=X", "nsu=URI;s=X" or "i=85" → the NodeId on this server.
  [[nodiscard]] Result<opcua::NodeId> parse(std::string_view text) const;
  // "nsu=URI;s=X" (namespace 0: "i=85").
  [[nodiscard]] std::string stable_text(const opcua::NodeId& id) const;

 private:
  std::vector<std::string> uris_;
};

struct DiscoveredVariable {
  opcua::NodeId node;
  std::string key;          // NamespaceTable::stable_text(node)
  std::string browse_path;  // "/Objects/Demo/Temperature"
  opcua::NodeId data_type;
  std::string unit;  // EngineeringUnits' display name, if the variable has that property
};

struct Discovery {
  std::vector<DiscoveredVariable> variables;  // each node once, in rule order
  std::vector<std::string> warnings;          // rules that matched nothing, nodes that failed
};

// The node a browse path names ("/Objects/Machines/M1/PackML", segments as SubscribeRule's), from
// the Root; Errc::not_found names the missing segment. `browse` replaces client.browse_children
// (a budget); empty: the client's.
Result<std::pair<opcua::NodeId, opcua::NodeClass>> resolve_browse_path(
    opcua::SyncClient& client, std::string_view path,
    const std::function<Result<std::vector<opcua::ReferenceDescription>>(const opcua::NodeId&)>& browse = {});

// Browses the model for `rules`; fails only when the connection fails (a rule that matches
// nothing is a warning).
Result<Discovery> discover(opcua::SyncClient& client, const NamespaceTable& namespaces,
                           const std::vector<SubscribeRule>& rules);

}  // namespace sf::cloud::detail
