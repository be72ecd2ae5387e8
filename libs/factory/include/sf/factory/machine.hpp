// MachineController: a shop-floor controller as the rest of the deployment
// sees it (paper §VII.A/B). The smart robot's IPC and every legacy machine's
// gateway implement it; the negotiation agent asks it for estimates and hands
// it awarded work, the OPC UA model shows its state and forwards operators'
// PackML commands. It never knows whether a plant simulation or real
// hardware answers below it.
//
// Concurrency contract: a controller is driven by one thread, the one that
// calls poll() (its cyclic loop in a process; the simulation's single thread
// on a ManualClock). Every other member is called from that same thread.
// Callbacks (on_job_end) run inside poll().
#pragma once

#include <chrono>
#include <cstdint>
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include "sf/core/clock.hpp"
#include "sf/core/result.hpp"
#include "sf/factory/packml.hpp"

namespace sf::factory {

// The operations of the candy line, the names products announce (Contract
// Net operation types) and the ontology's capabilities map to:
//   "upload"    box-loading    params: box_type (catalog index)
//   "load"      pick-and-place params: candy (catalog index), count, box (id), slot (first
//                              slot, 0-based, row by row), box_type (catalog index)
//   "download"  box-unloading  params: box (id)
//   "transport" conveying      params: box (id), from, to (place indexes: conveying.hpp, a
//                                      station or a belt's entry)
inline constexpr std::string_view kUpload = "upload";
inline constexpr std::string_view kLoad = "load";
inline constexpr std::string_view kDownload = "download";
inline constexpr std::string_view kTransport = "transport";

struct Operation {
  std::string type;                      // one of the names above
  std::map<std::string, double> params;  // as the Contract Net carries them
  [[nodiscard]] std::optional<double> param(std::string_view name) const;
  // A whole-number parameter within [lo, hi]; errors name the parameter and
  // say whether it is missing, not whole or out of range.
  [[nodiscard]] Result<std::int64_t> integer(std::string_view name, std::int64_t lo, std::int64_t hi) const;
};

// What a machine would take to do an operation now (the BID's content).
struct Estimate {
  std::chrono::nanoseconds start_in{0};  // until its queue is free
  std::chrono::nanoseconds duration{0};  // of the operation itself
  std::uint32_t queue_length = 0;
};

struct JobOutcome {
  std::string job;  // the id given to submit()
  bool ok = false;
  std::string detail;  // the result (e.g. "3 toffee in slots 4-6") or why it failed
  // What the product needs to go on, typed as Operation::params are: "box" (the id of an
  // uploaded box), "weight_g" and "count.<candy>" (an inspection), "placed" (candies loaded).
  std::map<std::string, double> results{};
};

// Machinery-style identification (OPC 40001-1 §8: Manufacturer, Model,
// SerialNumber, ...).
struct Identification {
  std::string name;  // the layout's machine name
  std::string kind;  // smart-robot, legacy-robot, conveyor, uploader, downloader
  std::string manufacturer;
  std::string model;
  std::string serial_number;
};

// A named process value for the OPC UA model: a robot's axis, a DI, a PLC
// register. Bad/uncertain quality carries its reason (PLC unreachable, stale).
struct Tag {
  enum class Quality : std::uint8_t { good, uncertain, bad };
  std::string name;  // "axis1.position", "plc.exit_eye"
  std::variant<bool, std::int64_t, double, std::string> value;
  Quality quality = Quality::good;
  std::string reason;  // why not good
  // Its EngineeringUnits (OPC 10000-8 §5.6.3) as a UNECE common code ("C81" radian, "MTR" metre,
  // "CEL" degree Celsius); empty: none (a count, a state).
  std::string unit{};
};

struct ControllerStatus {
  PackMLStatus packml;                 // state, mode, stop reason, counters
  std::optional<std::string> job;      // the job in work
  std::optional<Operation> operation;  // its operation
  std::uint32_t queued = 0;            // jobs waiting behind it
  // How long jobs were in work since the controller started: the machine's utilisation is this
  // over the time it ran (the demo's summary, the simulation's bottleneck bound).
  std::chrono::nanoseconds working_time{0};
  std::string fault;  // empty when none
  std::vector<Tag> tags;
};

class MachineController {
 public:
  virtual ~MachineController() = default;

  [[nodiscard]] virtual const Identification& identification() const = 0;
  // The operation types it can perform (its Contract Net skills).
  [[nodiscard]] virtual std::vector<std::string> operations() const = 0;
  // Whether and how fast it would do `op` now; nullopt when it would not bid
  // (not Execute/Idle, faulted, held, no stock of that candy, unknown
  // operation), with the reason in why_not.
  [[nodiscard]] virtual std::optional<Estimate> estimate(const Operation& op,
                                                         std::string* why_not = nullptr) const = 0;
  // Queues awarded work under `job` (an id unique among its jobs). Refused
  // (Errc::state) when estimate() would say no.
  virtual Status submit(const std::string& job, const Operation& op) = 0;
  // Drops a queued job, or aborts the one in work (its outcome: not ok).
  virtual Status cancel(const std::string& job) = 0;
  // An operator's PackML command (OPC 30050 / ISA-TR88.00.02): refused with
  // Errc::state when the state machine does not allow it.
  virtual Status command(PackMLCommand command) = 0;
  // One step of the controller's work at `now`: a cyclic exchange, a Modbus
  // poll, the next move of a job. Returns when it should be called again.
  virtual Clock::time_point poll(Clock::time_point now) = 0;
  [[nodiscard]] virtual ControllerStatus status() const = 0;
  // Whether a job is in work now (begun, not yet ended): what a machine's
  // utilisation counts, asked every cycle, so cheaper than status().
  [[nodiscard]] virtual bool working() const { return status().job.has_value(); }

  // Called from poll() when a submitted job ends.
  void on_job_end(std::function<void(const JobOutcome&)> callback) { on_job_end_ = std::move(callback); }

 protected:
  void job_ended(const JobOutcome& outcome) const {
    if (on_job_end_) {
      on_job_end_(outcome);
    }
  }

 private:
  std::function<void(const JobOutcome&)> on_job_end_;
};

}  // namespace sf::factory
