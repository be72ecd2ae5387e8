// Simulation: the deterministic mode of the factory (docs/factory.md). The
// plant, every shop-floor controller and the order service's products run in
// one process on one ManualClock, over in-memory links and transports:
//
//   plant ── in-memory EtherCAT segment ── our master ── SmartRobot ─┐
//         ── modbus::MemoryClient (the PLC's own request path) ── Gateway ─┤ MemoryNetwork
//                                                      OrderHost (products) ┘ (Contract Net)
//
// The controllers and agents are the deployment's own classes, unchanged;
// only the links are in memory and time is simulated, one millisecond per
// step (the EtherCAT cycle; gateways poll on their own period). A run with a
// given seed repeats exactly, so thousands of orders take seconds and a
// failing run can be replayed.
#pragma once

#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "sf/core/clock.hpp"
#include "sf/core/result.hpp"
#include "sf/factory/order_host.hpp"
#include "sf/line/layout.hpp"

namespace sf::plant {
class Plant;
}

namespace sf::simulation {

// Who decides the products' machines and routes: the Contract Net (the
// factory's way), or the central dispatcher the scheduling benchmark compares
// it with (central_dispatcher.hpp).
enum class Decisions : std::uint8_t { contract_net, central_dispatcher };

struct SimulationOptions {
  std::uint64_t seed = 1;
  factory::OrderHostOptions host;
  Decisions decisions = Decisions::contract_net;
};

// How long a machine had a job in work (MachineController::working), sampled
// every step: the utilisation the bottleneck bound is computed from.
struct MachineLoad {
  std::string machine;
  std::chrono::nanoseconds working{0};
};

// One line of the run's log: an order's event or the plant's, in time order.
struct LogLine {
  std::chrono::nanoseconds at{};
  std::string text;
  friend bool operator==(const LogLine&, const LogLine&) = default;
};

class Simulation {
 public:
  // Builds the plant and a controller for each of its machines, all started
  // (PackML Execute); errors: a machine that does not come up, a layout whose
  // operations no machine can do.
  static Result<std::unique_ptr<Simulation>> create(line::Layout layout, SimulationOptions options = {});
  ~Simulation();
  Simulation(const Simulation&) = delete;
  Simulation& operator=(const Simulation&) = delete;

  Status submit(factory::Order order);
  // One millisecond of the whole line.
  void step();
  // Steps until `done` or `limit` of simulated time has passed; whether `done` came true.
  bool run_until(const std::function<bool()>& done, std::chrono::nanoseconds limit);

  // A controller's process dies (kill -9): it is polled no more (a smart robot's master stops
  // cycling, so its slave leaves OP by its watchdog; a gateway stops polling its PLC) and its
  // Contract Net traffic stops (the products see its liveliness lost after the lease).
  Status kill(const std::string& machine);
  // The controller's DDS link is cut (a network partition): it goes on working, but its Contract
  // Net messages, and those to it, wait until reconnect() (MemoryNetwork::cut_off).
  Status cut_off(const std::string& machine);
  Status reconnect(const std::string& machine);
  // A plant fault as `plant faults` names them, e.g. "jam:conveyor2" (plant/faults.hpp).
  Status inject(std::string_view fault);
  Status clear(std::string_view fault);

  [[nodiscard]] Clock::time_point now() const;
  [[nodiscard]] const factory::OrderHost& host() const;
  [[nodiscard]] const plant::Plant& plant() const;
  // The orders' events and the plant's, merged in time order.
  [[nodiscard]] std::vector<LogLine> log() const;
  [[nodiscard]] const std::vector<factory::OrderEvent>& order_events() const;
  // Contract Net messages sent so far (both domains).
  [[nodiscard]] std::uint64_t messages() const;
  // Every machine's time in work so far, in layout order.
  [[nodiscard]] std::vector<MachineLoad> loads() const;
  // The products' waits for decisions (an operation until its machine is confirmed, a route
  // until it is composed) and their time on the line (admitted to settled), both summed.
  [[nodiscard]] std::chrono::nanoseconds deciding() const;
  [[nodiscard]] std::chrono::nanoseconds on_line() const;

 private:
  struct Parts;
  explicit Simulation(std::unique_ptr<Parts> parts);
  std::unique_ptr<Parts> parts_;
};

}  // namespace sf::simulation
