// The cloud gateway's configuration (cloud.yaml): the OPC UA servers it is a client of, what it
// subscribes to on each, the historian it writes to, and the aggregating OPC UA server through
// which supervisory clients read history. Errors name file:line:column and the key path.
//
//   historian:
//     url: sqlite:/var/lib/smartfactory/history.db     # or postgresql://user@host:5432/db
//     buffer: /var/lib/smartfactory/buffer            # store-and-forward directory
//     batch: 1000                                     # samples per database write
//     flush_ms: 200                                   # the oldest sample waits at most this long
//   servers:
//     - name: line-1
//       url: opc.tcp://10.0.0.5:4840
//       publishing_interval_ms: 100
//       sampling_interval_ms: 100
//       queue_size: 10
//       events: true                                  # events of the Server object
//       security: Basic256Sha256:SignAndEncrypt       # or auto (the most secure offered), none
//       user: gateway                                 # UserName login (default: anonymous)
//       password_file: /etc/smartfactory/gateway.pw   #   or user_certificate + user_key
//       subscribe:
//         - browse_path: /Objects/Demo                # the Variables below a node (depth levels)
//           depth: 3
//         - node: nsu=urn:smartfactory:demo;s=Demo.Counter
//         - type: nsu=urn:example;i=1000              # every instance of an ObjectType
//   discovery:                                        # more servers, found with FindServers
//     url: opc.tcp://lds:4840
//     interval_s: 30                                  # asked again this often for new servers
//     subscribe: [{browse_path: /Objects}]            # + the settings of a server entry
//   aggregating_server:
//     port: 4850
//     security: sign,encrypt                          # none, sign, encrypt (a comma list)
//     users: /etc/smartfactory/users.yaml             # UserName/X509 users and roles
//     anonymous: viewer                               # the role of anonymous users, or off
//   pki: /var/lib/smartfactory/pki                    # own certificate and trust lists
//   knowledge:                                        # the knowledge loop (knowledge_loop.hpp)
//     layout: /etc/smartfactory/line.yaml             # the line's layout (default: built in)
//     ontology: /etc/smartfactory/candy-factory.ttl   # default: the built-in ontology
//     rules: /etc/smartfactory/candy-factory.rules    # default: the built-in rules
//     due_after_s: 900                                # an order's box is late after this (0: never)
#pragma once

#include <chrono>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "sf/core/result.hpp"

namespace sf::cloud {

// One of browse_path, node or type.
struct SubscribeRule {
  // "/Objects/Demo/Temperature": browse names from the Root, each "Name", "2:Name" (namespace
  // index of the server) or any namespace when no index is given.
  std::string browse_path;
  // A NodeId, "ns=2;s=X" or "nsu=URI;s=X" (namespace by URI, stable across server restarts).
  std::string node;
  // An ObjectType: its instances (and those of its subtypes) anywhere below Objects.
  std::string type;
  // Levels of hierarchical references followed below the node or instance for Variables.
  unsigned depth = 3;
};

// How the gateway connects to a server (OPC 10000-4 §5.4.4, §5.6.3). The gateway hands these to
// GatewayOptions::configure_client; `smartfactory cloud` applies them with its PKI folder.
struct ConnectionSecurity {
  std::string security = "auto";  // POLICY:MODE (e.g. Basic256Sha256:SignAndEncrypt), none, auto
  std::string user;               // UserName login, password from password_file
  std::string password_file;
  std::string user_certificate;  // X509 login
  std::string user_key;
};

struct ServerConfig {
  std::string name;  // unique; the series' server key and the folder of the aggregating server
  std::string url;   // opc.tcp://host:port[/path]
  double publishing_interval_ms = 100;
  double sampling_interval_ms = 100;
  std::uint32_t queue_size = 10;
  bool events = false;
  // How often the subscribe rules are matched against the server's model again once subscribed:
  // variables it adds later (a controller's tags appear with its first publication) are then
  // subscribed too. 0: only when connecting.
  std::chrono::seconds rediscover{10};
  std::vector<SubscribeRule> subscribe;
  ConnectionSecurity security;
};

struct HistorianConfig {
  std::string url = "sqlite:history.db";
  std::filesystem::path buffer = "history.buffer";
  std::size_t batch = 1000;
  std::chrono::milliseconds flush_interval{200};
};

struct DiscoveryConfig {
  std::string url;
  std::chrono::seconds interval{30};
  // What to subscribe to on every server FindServers returns (name: its ApplicationUri).
  ServerConfig defaults;
};

struct AggregatingServerConfig {
  bool enabled = false;
  std::string host = "0.0.0.0";
  std::uint16_t port = 4850;
  // Applied by GatewayOptions::configure_aggregating_server (smartfactory cloud: as `opcua server`
  // --security, --policies, --users, --anonymous; empty policies: all three).
  std::string security = "sign,encrypt";
  std::string policies;
  std::string users;
  std::string anonymous;
};

// The knowledge loop: present in the file = on. Empty paths: the built-in files.
struct KnowledgeConfig {
  std::filesystem::path layout;
  std::filesystem::path ontology;
  std::filesystem::path rules;
  std::chrono::seconds due_after{0};
};

struct GatewayConfig {
  std::vector<ServerConfig> servers;
  std::optional<KnowledgeConfig> knowledge;
  std::optional<DiscoveryConfig> discovery;
  HistorianConfig historian;
  AggregatingServerConfig aggregating_server;
  std::string pki;  // the PKI folder; empty: the installation's default
};

Result<GatewayConfig> load_gateway_config(const std::filesystem::path& file);
// `name` stands for the file name in errors.
Result<GatewayConfig> parse_gateway_config(std::string_view yaml, std::string name = "<config>");

}  // namespace sf::cloud
