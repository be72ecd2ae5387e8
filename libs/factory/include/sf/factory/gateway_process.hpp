// The gateway as the process that runs next to a legacy machine
// (`smartfactory gateway --config FILE`, paper §VII.B): the machine's PLC
// over Modbus TCP, the Gateway driven by its ControllerThread (a poll every
// poll period), its model on the process's OPC UA server (the `opcua:`
// settings: port, security, users, the ontology's NodeSet2; ModelServer) and
// its roles in the Contract Net over Cyclone DDS (gateway_agent.hpp) on the
// agents' loop (negotiation::run_agents, the calling thread of run()). The
// roles reach the gateway through a RemoteController: bids, awards and
// transport REQUESTs become calls on the controller's thread, job ends come
// back through the DDS executor. The OPC UA server's loop thread reads the
// controller thread's snapshots and posts operators' PackML commands there.
#pragma once

#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "sf/core/clock.hpp"
#include "sf/core/result.hpp"
#include "sf/dds/executor.hpp"
#include "sf/factory/controller_process.hpp"
#include "sf/factory/controller_thread.hpp"
#include "sf/factory/gateway.hpp"
#include "sf/factory/gateway_agent.hpp"
#include "sf/factory/gateway_config.hpp"
#include "sf/modbus/tcp_client.hpp"
#include "sf/negotiation/dds_transport.hpp"

namespace sf::factory {

// What the process reports: the controller's status and its part in the Contract Net.
struct GatewayReport {
  Identification identification;
  std::string endpoint;        // the PLC's Modbus TCP address
  std::string link;            // "up", "stale", "lost" (or "unknown" before the first poll)
  std::string opcua_endpoint;  // opc.tcp://host:port
  std::string opcua_security;  // what the server's security came to
  ControllerStatus controller;
  negotiation::ContractorStats contract_net;
  std::uint64_t informs = 0;  // a conveyor's INFORMs (segments offered)
  std::uint64_t silent = 0;   // REQUESTs a conveyor left unanswered (it took no work)
};

class GatewayProcess {
 public:
  // `setup` is a checked configuration (load_gateway_config); `clock` is the process's (real
  // time in deployment) and must outlive it. The OPC UA server serves from here on; the gateway
  // is polled from run() on. Nothing is left running when this fails.
  static Result<std::unique_ptr<GatewayProcess>> create(GatewaySetup setup, Clock& clock);
  ~GatewayProcess();
  GatewayProcess(const GatewayProcess&) = delete;
  GatewayProcess& operator=(const GatewayProcess&) = delete;

  // Starts the controller's thread and runs the agents' loop on the calling thread until stop()
  // is true (checked at least every 100 ms). on_report gets a report on that thread every
  // `interval` (0: never for time alone) and whenever the PackML state, the link, the job in
  // work or the queue changed. The controller's thread stops before run returns.
  void run(const std::function<bool()>& stop, const std::function<void(const GatewayReport&)>& on_report,
           std::chrono::nanoseconds interval);

  [[nodiscard]] GatewayReport report() const;
  // The gateway's configuration and what follows from it alone (operations, segments, layout):
  // its mutable state belongs to the controller's thread.
  [[nodiscard]] const Gateway& gateway() const { return *gateway_; }
  [[nodiscard]] const GatewayAgent& agent() const { return *agent_; }
  [[nodiscard]] opcua::server::Server& opcua_server() { return hosted_->model().server(); }
  [[nodiscard]] const MachineHost& machine_model() const { return hosted_->model().host(); }

 private:
  GatewayProcess(GatewaySetup setup, std::unique_ptr<modbus::TcpClient> client, Clock& clock);

  std::unique_ptr<modbus::TcpClient> client_;
  std::unique_ptr<Gateway> gateway_;
  std::unique_ptr<HostedController> hosted_;  // its job ends go to the executor
  dds::Executor executor_;
  std::unique_ptr<GatewayAgent> agent_;  // after the executor: its readers deliver there
};

}  // namespace sf::factory
