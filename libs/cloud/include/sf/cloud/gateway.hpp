// The cloud gateway (paper §V.B, Fig. 6): an OPC UA client of every shop-floor server that
// delivers real-time data and events to in-process applications (LiveBus) and historical data and
// events to the historian, and an aggregating OPC UA server through which supervisory clients
// read that history (HistoryRead).
//
//   auto gateway = Gateway::create(config);           // opens the historian (store-and-forward)
//   auto on = gateway->live().subscribe([](const LiveUpdate& u) { ... });
//   gateway->start();                                  // servers connect in the background
//   ... gateway->status() ...
//   gateway->stop();                                   // queued samples are written first
//
// A server that does not answer, or answers wrongly, is retried and reported in status(); the
// others keep working. A database that is away is bridged by the durable buffer.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "sf/cloud/config.hpp"
#include "sf/cloud/knowledge_loop.hpp"
#include "sf/cloud/live_bus.hpp"
#include "sf/core/clock.hpp"
#include "sf/historian/buffered_store.hpp"
#include "sf/opcua/client/client.hpp"
#include "sf/opcua/server/server.hpp"

namespace sf::cloud {

struct ServerStatus {
  std::string name;
  std::string url;
  // "connecting", "discovering", "subscribed", "reconnecting", "stopped"
  std::string phase;
  bool connected = false;
  std::size_t series = 0;
  std::uint64_t samples = 0;
  std::uint64_t events = 0;
  std::string last_error;
  std::vector<std::string> warnings;  // rules that matched nothing, ...
};

struct DiscoveryStatus {
  std::string url;
  std::size_t found = 0;  // servers added from FindServers answers
  std::string last_error;
};

struct GatewayStatus {
  std::vector<ServerStatus> servers;
  std::optional<DiscoveryStatus> discovery;
  std::uint64_t samples_received = 0;
  std::uint64_t samples_written = 0;
  std::uint64_t samples_failed = 0;
  std::uint64_t events_written = 0;
  std::size_t queued = 0;
  historian::BufferStats buffer;
  std::uint16_t aggregating_port = 0;  // 0 when not running
};

// Called after each batch the historian accepted (latency measurements).
using CommitObserver = std::function<void(std::span<const historian::Sample>)>;

// The gateway's seams. Security is provisioned by the application (certificates, PKI folder,
// passwords): the library hands each connection's and the aggregating server's configuration to
// these hooks, whose error stops start() (a bad setting) or that server only (a discovered one).
struct GatewayOptions {
  Clock* clock = &SteadyClock::instance();
  CommitObserver on_commit;
  std::function<Status(const ServerConfig&, opcua::ClientConfig&)> configure_client;
  std::function<Status(const AggregatingServerConfig&, opcua::server::ServerConfig&)>
      configure_aggregating_server;
};

class Gateway {
 public:
  static Result<std::unique_ptr<Gateway>> create(GatewayConfig config, GatewayOptions options = {});
  ~Gateway();
  Gateway(const Gateway&) = delete;
  Gateway& operator=(const Gateway&) = delete;

  // Starts every server connection, discovery and the aggregating server (whose port must be
  // free). Fails on settings the hooks refuse.
  Status start();
  void stop();

  [[nodiscard]] GatewayStatus status() const;
  LiveBus& live();
  historian::Store& store();
  // Calls a method on the server named `server` (ServerConfig::name): the Object by its browse
  // path from the Root and the method by its browse name, e.g. ("line-1",
  // "/Objects/OrderService", "SubmitOrder", ...). Errc::not_found for an unknown server; else
  // as the server answers (Errc::state while it is not connected). Any thread; blocks.
  Result<std::vector<opcua::Variant>> call(std::string_view server, const std::string& object_path,
                                           const std::string& method, std::vector<opcua::Variant> inputs);
  // The knowledge loop when the configuration has one (alarms, its status); else null.
  [[nodiscard]] const KnowledgeLoop* knowledge() const;
  // The same, to acknowledge its alarms (KnowledgeLoop::acknowledge).
  [[nodiscard]] KnowledgeLoop* knowledge();

  struct Impl;

 private:
  explicit Gateway(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

}  // namespace sf::cloud
