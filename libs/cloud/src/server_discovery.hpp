// The gateway's discovery (paper §V.B: the cloud finds the shop floor's servers): FindServers
// (OPC 10000-4 §5.4.2) on the configured discovery URL — a Local Discovery Server lists the
// servers registered with it, a server lists itself — now and every interval; each server not
// seen before becomes a server entry with the discovery's subscribe settings.
#pragma once

#include <condition_variable>
#include <functional>
#include <mutex>
#include <set>
#include <string>
#include <thread>
#include <vector>

#include "sf/cloud/config.hpp"
#include "sf/cloud/gateway.hpp"
#include "sf/opcua/types.hpp"

namespace sf::cloud::detail {

// The server entries for what FindServers returned: Servers (and ClientAndServers) with an
// opc.tcp discovery URL not in `known_urls`, named by their ApplicationUri ("uri@host:port" when
// that name is taken, e.g. by servers sharing a certificate). Adds their URLs to known_urls.
std::vector<ServerConfig> servers_found(const std::vector<opcua::ApplicationDescription>& found,
                                        const DiscoveryConfig& discovery, std::set<std::string>& known_urls,
                                        std::set<std::string>& known_names);

class ServerDiscovery {
 public:
  // add_server is called on the discovery thread for each new server.
  ServerDiscovery(DiscoveryConfig config, std::set<std::string> known_urls, std::set<std::string> known_names,
                  std::function<void(ServerConfig)> add_server);
  ~ServerDiscovery();
  ServerDiscovery(const ServerDiscovery&) = delete;
  ServerDiscovery& operator=(const ServerDiscovery&) = delete;

  void start();
  void stop();
  [[nodiscard]] DiscoveryStatus status() const;

 private:
  void run();
  void find_once();

  DiscoveryConfig config_;
  std::function<void(ServerConfig)> add_server_;
  std::set<std::string> known_urls_;   // discovery thread only
  std::set<std::string> known_names_;  // discovery thread only

  mutable std::mutex mutex_;
  std::condition_variable wake_;
  bool stopping_ = false;
  DiscoveryStatus status_;
  std::thread thread_;
};

}  // namespace sf::cloud::detail
