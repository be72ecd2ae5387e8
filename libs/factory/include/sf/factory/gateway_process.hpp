// The gateway as the process that runs next to a legacy machine
// (`smartfactory gateway --config FILE`, paper §VII.B): the machine's PLC
// over Modbus TCP, the Gateway's poll loop on the process's clock, and its
// roles in the Contract Net over Cyclone DDS (gateway_agent.hpp), all on one
// thread: the agents' loop (negotiation::run_agents) polls the gateway when
// its period is due and handles DDS messages between polls.
//
// The OPC UA model of the controller attaches here: the process owns the
// Gateway and hands it out (gateway()); on_poll() runs a hook on the loop's
// thread after every poll, where a model reads status() and applies
// operators' PackML commands, as the MachineController contract asks (one
// thread drives a controller). The process itself serves no OPC UA.
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
#include "sf/factory/gateway.hpp"
#include "sf/factory/gateway_agent.hpp"
#include "sf/factory/gateway_config.hpp"
#include "sf/modbus/tcp_client.hpp"
#include "sf/negotiation/dds_transport.hpp"

namespace sf::factory {

// What the process reports: the controller's status and its part in the Contract Net.
struct GatewayReport {
  Identification identification;
  std::string endpoint;  // the PLC's Modbus TCP address
  std::string link;      // "up", "stale", "lost" (or "unknown" before the first poll)
  ControllerStatus controller;
  negotiation::ContractorStats contract_net;
  std::uint64_t informs = 0;  // a conveyor's INFORMs (segments offered)
  std::uint64_t silent = 0;   // REQUESTs a conveyor left unanswered (it took no work)
};

class GatewayProcess {
 public:
  // `setup` is a checked configuration (load_gateway_config); `clock` is the process's (real
  // time in deployment) and must outlive it. Nothing is started yet when this fails.
  static Result<std::unique_ptr<GatewayProcess>> create(GatewaySetup setup, const Clock& clock);
  ~GatewayProcess();
  GatewayProcess(const GatewayProcess&) = delete;
  GatewayProcess& operator=(const GatewayProcess&) = delete;

  // Runs the loop until stop() is true (checked on the loop's thread at least every 100 ms).
  // on_report gets a report on the loop's thread every `interval` and whenever the PackML
  // state, the link, the job in work or the queue changed.
  void run(const std::function<bool()>& stop, const std::function<void(const GatewayReport&)>& on_report,
           std::chrono::nanoseconds interval);
  // Runs `hook` on the loop's thread after every poll of the gateway (the OPC UA model's place).
  void on_poll(std::function<void(Gateway&)> hook);

  [[nodiscard]] GatewayReport report() const;
  [[nodiscard]] Gateway& gateway() { return *gateway_; }
  [[nodiscard]] const Gateway& gateway() const { return *gateway_; }
  [[nodiscard]] const GatewayAgent& agent() const { return *agent_; }

 private:
  GatewayProcess(GatewaySetup setup, std::unique_ptr<modbus::TcpClient> client, const Clock& clock);
  void after_poll(Clock::time_point now);

  const Clock* clock_;
  std::unique_ptr<modbus::TcpClient> client_;
  std::unique_ptr<Gateway> gateway_;
  dds::Executor executor_;
  std::unique_ptr<GatewayAgent> agent_;  // after the executor: its readers deliver there
  std::vector<std::function<void(Gateway&)>> hooks_;
  std::function<void(const GatewayReport&)> on_report_;
  std::chrono::nanoseconds interval_{0};
  Clock::time_point next_report_{};
  std::string last_shown_;  // state, link, job and queue of the last report
};

}  // namespace sf::factory
