#include "server_discovery.hpp"

#include <fmt/format.h>

#include <chrono>

#include "sf/core/log.hpp"
#include "sf/opcua/client/client.hpp"

namespace sf::cloud::detail {

namespace {

namespace ua = sf::opcua;
using namespace std::chrono_literals;

// "host:port" of opc.tcp://host:port/path.
std::string authority(std::string_view url) {
  url.remove_prefix(std::string_view("opc.tcp://").size());
  return std::string(url.substr(0, url.find('/')));
}

const ua::String* tcp_url(const ua::ApplicationDescription& app) {
  for (const ua::String& url : app.discovery_urls) {
    if (url.view().starts_with("opc.tcp://") && url.view().size() > 10) {
      return &url;
    }
  }
  return nullptr;
}

}  // namespace

std::vector<ServerConfig> servers_found(const std::vector<ua::ApplicationDescription>& found,
                                        const DiscoveryConfig& discovery, std::set<std::string>& known_urls,
                                        std::set<std::string>& known_names) {
  std::vector<ServerConfig> added;
  for (const ua::ApplicationDescription& app : found) {
    // OPC 10000-4 §7.2: a DiscoveryServer (the LDS itself) has no data to collect.
    if (app.application_type != ua::ApplicationType::Server &&
        app.application_type != ua::ApplicationType::ClientAndServer) {
      continue;
    }
    const ua::String* url = tcp_url(app);
    if (url == nullptr || !known_urls.insert(url->str()).second) {
      continue;
    }
    ServerConfig server = discovery.defaults;
    server.url = url->str();
    std::string name = app.application_uri.view().empty() ? authority(server.url) : app.application_uri.str();
    if (known_names.contains(name)) {
      name += "@" + authority(server.url);
    }
    // The name is a folder of the aggregating server and a series key: no '/'.
    for (char& c : name) {
      c = c == '/' ? '_' : c;
    }
    known_names.insert(name);
    server.name = std::move(name);
    added.push_back(std::move(server));
  }
  return added;
}

ServerDiscovery::ServerDiscovery(DiscoveryConfig config, std::set<std::string> known_urls,
                                 std::set<std::string> known_names,
                                 std::function<void(ServerConfig)> add_server)
    : config_(std::move(config)),
      add_server_(std::move(add_server)),
      known_urls_(std::move(known_urls)),
      known_names_(std::move(known_names)) {
  status_.url = config_.url;
}

ServerDiscovery::~ServerDiscovery() {
  stop();
}

void ServerDiscovery::start() {
  thread_ = std::thread([this] { run(); });
}

void ServerDiscovery::stop() {
  {
    std::lock_guard lock(mutex_);
    stopping_ = true;
  }
  wake_.notify_all();
  if (thread_.joinable()) {
    thread_.join();
  }
}

DiscoveryStatus ServerDiscovery::status() const {
  std::lock_guard lock(mutex_);
  return status_;
}

void ServerDiscovery::run() {
  while (true) {
    find_once();
    std::unique_lock lock(mutex_);
    if (wake_.wait_for(lock, config_.interval, [this] { return stopping_; })) {
      return;
    }
  }
}

// FindServers needs no session and is served on a SecurityPolicy None channel (§5.4).
void ServerDiscovery::find_once() {
  ua::ClientConfig client_config;
  client_config.endpoint_url = config_.url;
  client_config.request_timeout = 10s;
  ua::SyncClient client(client_config);
  auto found = client.find_servers();
  if (!found) {
    log::get("cloud")->warn("discovery {}: {}", config_.url, found.error().message);
    std::lock_guard lock(mutex_);
    status_.last_error = found.error().message;
    return;
  }
  const std::vector<ServerConfig> added = servers_found(*found, config_, known_urls_, known_names_);
  {
    std::lock_guard lock(mutex_);
    status_.last_error.clear();
    status_.found += added.size();
  }
  for (const ServerConfig& server : added) {
    log::get("cloud")->info("discovery {}: found {} at {}", config_.url, server.name, server.url);
    add_server_(server);
  }
}

}  // namespace sf::cloud::detail
