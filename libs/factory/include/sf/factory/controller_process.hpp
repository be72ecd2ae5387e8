// What the `machine` and `gateway` processes share (paper §VII.A, §VII.B): each serves its
// controller's model on an OPC UA server of its own (ModelServer), and reports its status on the
// agents' loop (StatusReporter).
#pragma once

#include <chrono>
#include <functional>
#include <memory>
#include <optional>
#include <string>

#include "sf/core/clock.hpp"
#include "sf/core/result.hpp"
#include "sf/dds/executor.hpp"
#include "sf/factory/controller_config.hpp"
#include "sf/factory/controller_thread.hpp"
#include "sf/factory/machine_host.hpp"
#include "sf/negotiation/agents.hpp"
#include "sf/opcua/server/server.hpp"

namespace sf::factory {

// Values a shop-floor server keeps per Historizing variable: at the rate a controller
// publishes, minutes of its state and tags (the cloud's outage it can bridge).
inline constexpr std::size_t kHistoryDepth = 10'000;
// An OPC UA server from a process's `opcua:` settings (port, security, users), not started yet,
// with a MemoryHistory of its Historizing variables; `security` is what its security came to
// (policies, modes, users). The controllers' ModelServer and the order service start theirs
// from here.
Result<std::unique_ptr<opcua::server::Server>> settings_server(const ControllerSettings& settings,
                                                               Clock& clock, std::string& security);
// The URL of a server from settings_server: opc.tcp://<opcua host, or localhost>:<port>.
std::string settings_endpoint(const std::string& opcua_host, std::uint16_t port);

// A controller's OPC UA server from its `opcua:` settings (port, security, users, the
// ontology's NodeSet2 files, imported first so the machine object is its individual), with
// the model of the controller `thread` drives (MachineHost), serving. Declare it after the
// ControllerThread: it must go first (the host before the thread).
class ModelServer {
 public:
  static Result<std::unique_ptr<ModelServer>> start(const ControllerSettings& settings,
                                                    ControllerThread& thread,
                                                    const Identification& identification, Clock& clock);
  ~ModelServer();
  ModelServer(const ModelServer&) = delete;
  ModelServer& operator=(const ModelServer&) = delete;

  [[nodiscard]] opcua::server::Server& server() { return *server_; }
  [[nodiscard]] const opcua::server::Server& server() const { return *server_; }
  [[nodiscard]] const MachineHost& host() const { return *host_; }
  // opc.tcp://<its opcua host, or localhost>:<port>
  [[nodiscard]] std::string endpoint() const;
  // What the server's security came to (policies, modes, users).
  [[nodiscard]] const std::string& security() const { return security_; }

 private:
  ModelServer() = default;

  std::unique_ptr<opcua::server::Server> server_;
  std::unique_ptr<MachineHost> host_;
  std::string host_name_;  // the opcua host of its settings
  std::string security_;
};

// A process's controller on its ControllerThread, its model served (ModelServer) and the
// RemoteController through which the process's other thread (the agents' loop) reaches it; job
// ends go to `deliver` (e.g. the DDS executor's post). Nothing is polled before start().
class HostedController {
 public:
  static Result<std::unique_ptr<HostedController>> create(MachineController& controller,
                                                          const ControllerSettings& settings,
                                                          ControllerThreadOptions options, Clock& clock,
                                                          std::function<void(std::function<void()>)> deliver);
  // Stops the thread, then the server.
  ~HostedController();
  HostedController(const HostedController&) = delete;
  HostedController& operator=(const HostedController&) = delete;

  // What run() reports: `headline` is what a status line shows (state, job, queue...); `report`
  // is called every `interval` (0: never for time alone) and soon after the headline changed.
  struct Reports {
    std::function<std::string()> headline;
    std::function<void()> report;
    std::chrono::nanoseconds interval{0};
  };
  // Starts the controller's thread, runs the agents' loop (negotiation::run_agents) with
  // `agent` and the reports on the calling thread until stop() is true, stops the thread.
  void run(dds::Executor& executor, negotiation::Agent& agent, const std::function<bool()>& stop,
           Reports reports);

  [[nodiscard]] ControllerThread& thread() { return *thread_; }
  [[nodiscard]] const ControllerThread& thread() const { return *thread_; }
  [[nodiscard]] RemoteController& remote() { return *remote_; }
  [[nodiscard]] ModelServer& model() { return *model_; }
  [[nodiscard]] const ModelServer& model() const { return *model_; }

 private:
  HostedController() = default;

  Clock* clock_ = nullptr;
  std::unique_ptr<ControllerThread> thread_;
  std::unique_ptr<ModelServer> model_;  // after the thread: goes first
  std::unique_ptr<RemoteController> remote_;
};

// Calls `report` on the agents' loop every `interval`, and soon after `headline` (what a
// status line shows: state, job, queue...) changed.
class StatusReporter final : public negotiation::Agent {
 public:
  StatusReporter(const Clock& clock, std::function<std::string()> headline, std::function<void()> report,
                 std::chrono::nanoseconds interval)
      : clock_(&clock), headline_(std::move(headline)), report_(std::move(report)), interval_(interval) {}

  void tick() override;
  [[nodiscard]] std::optional<Clock::time_point> next_deadline() const override;

 private:
  const Clock* clock_;
  std::function<std::string()> headline_;
  std::function<void()> report_;
  std::chrono::nanoseconds interval_;
  Clock::time_point next_{};
  std::string last_;
};

}  // namespace sf::factory
