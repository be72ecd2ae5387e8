// An OPC UA server: namespace 0, the Server object with live status, the application's
// information model, UA-TCP on a port, sessions, services and subscriptions, all on one loop
// thread. Application code reaches the address space through with_address_space(), which runs
// on that thread, so no lock is needed anywhere else.
//
//   Server server(config);
//   server.with_address_space([](AddressSpace& space) { /* add nodes */ });
//   if (auto st = server.start(); !st) { ... }
//   ...
//   server.stop();
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <string>

#include "sf/core/clock.hpp"
#include "sf/core/result.hpp"
#include "sf/net/event_loop.hpp"
#include "sf/opcua/server/address_space.hpp"
#include "sf/opcua/server/dispatcher.hpp"
#include "sf/opcua/transport/server_transport.hpp"

namespace sf::opcua::server {

struct ServerConfig {
  ServerIdentity identity;
  // Host in the endpoint URL the server advertises when a client names none; empty = the
  // machine's host name.
  std::string advertised_host;
  ServerTransportConfig transport;
  // Endpoints, certificate, trust, users and roles (security.hpp); the default is None and
  // unrestricted anonymous access. Overrides transport.policies/credentials/validate_certificate.
  ServerSecurity security;
  SessionLimits sessions;
  SubscriptionLimits subscriptions;
  OperationLimits operations;
  std::string software_version = "0.1.0";
};

class Server {
 public:
  explicit Server(ServerConfig config, const Clock& clock = SteadyClock::instance());
  ~Server();
  Server(const Server&) = delete;
  Server& operator=(const Server&) = delete;

  // Binds the port and starts serving; errors name host:port.
  Status start();
  // Closes every channel and stops the loop thread. Idempotent; the destructor calls it.
  void stop();

  // Runs fn with the address space on the loop thread and waits for it (directly when called
  // on the loop thread, e.g. from a value callback or timer).
  void with_address_space(const std::function<void(AddressSpace&)>& fn);
  // The loop the server runs on, for the application's timers (e.g. a simulated sensor).
  net::EventLoop& loop();

  // Where HistoryRead finds the history of Variables with AccessLevel HistoryRead (see
  // history.hpp); any thread.
  void set_history_database(std::shared_ptr<HistoryDatabase> database);
  // The retained conditions ConditionRefresh reports (Dispatcher::set_condition_refresh); any
  // thread, the source is called on the loop thread.
  void set_condition_refresh(Dispatcher::ConditionSource conditions);

  // Reports an event to subscribers of `notifier` and of the Server object. Any thread.
  void raise_event(const NodeId& notifier, SubscriptionService::Event event);

  [[nodiscard]] std::uint16_t port() const;
  // "opc.tcp://<advertised host>:<port>".
  [[nodiscard]] std::string endpoint_url() const;
  [[nodiscard]] std::size_t session_count();
  [[nodiscard]] std::size_t subscription_count();
  [[nodiscard]] std::size_t monitored_item_count();

 private:
  void schedule_tick();
  void on_tick();
  template <typename T>
  T on_loop(const std::function<T()>& fn);

  ServerConfig config_;
  const Clock& clock_;
  AddressSpace space_;
  std::unique_ptr<net::LoopThread> thread_;
  std::unique_ptr<Dispatcher> dispatcher_;
  std::shared_ptr<HistoryDatabase> history_;
  Dispatcher::ConditionSource conditions_;
  std::unique_ptr<ServerTransport> transport_;
  net::EventLoop::TimerId tick_timer_ = 0;
  Clock::time_point tick_at_ = Clock::time_point::max();
  std::uint16_t port_ = 0;
  ServerState state_ = ServerState::Suspended;
};

}  // namespace sf::opcua::server
