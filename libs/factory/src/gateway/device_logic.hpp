// DeviceLogic: what differs between the kinds of legacy machine behind a
// gateway (conveyor, uploader, downloader, legacy robot). The gateway core
// (gateway.cpp) owns the poll loop, the link's health, the PackML unit and
// the job queue; it hands the job in work to the logic once per poll, with
// the device's registers freshly read into PlcIo.
#pragma once

#include <chrono>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "plc_io.hpp"
#include "sf/factory/gateway_config.hpp"
#include "sf/factory/machine.hpp"

namespace sf::factory::gateway {

struct JobResult {
  bool ok = false;
  std::string detail;
  std::map<std::string, double> results;
  // A fault of the machine rather than of this job (a jam, an axis): the unit aborts with it.
  std::optional<StopReason> machine_fault;
};

class DeviceLogic {
 public:
  virtual ~DeviceLogic() = default;

  [[nodiscard]] virtual std::vector<std::string> operations() const = 0;
  [[nodiscard]] virtual std::string tag_prefix() const { return "plc"; }
  [[nodiscard]] virtual std::vector<TagSpec> tags() const = 0;
  // How long `op` takes on this machine once begun, or why it would not do it.
  [[nodiscard]] virtual Result<std::chrono::nanoseconds> duration(const Operation& op) const = 0;

  // Whether a queued job of `op` may come into work now: its box stands at the
  // machine's station, its way is clear. The first ready job of the queue begins.
  [[nodiscard]] virtual bool ready(const Operation& /*op*/, const PlcIo& /*io*/) const { return true; }
  // A job comes into work (duration() accepted its operation).
  virtual void begin(const Operation& op) = 0;
  // One poll of the job in work. `go` false: start no new step on the device (Holding,
  // Stopping, a cancel), but follow one that runs; a belt stops. The result once it ended.
  virtual std::optional<JobResult> step(PlcIo& io, bool go) = 0;
  // No step of the job runs on the device: the job can be held, failed or put aside now.
  [[nodiscard]] virtual bool settled() const = 0;
  // The job in work ends early, for `why`: the result says how far it got.
  [[nodiscard]] virtual JobResult interrupted(const std::string& why) const = 0;
  // Outputs to their safe state (belt motor off, start cleared); the step in work is dropped.
  virtual void halt(PlcIo& io) = 0;
  // PackML Resetting: a latched fault reset, outputs to their idle state. True when done.
  virtual bool reset(PlcIo& io) = 0;
  // A fault the device shows by itself, outside any job (a jammed belt).
  [[nodiscard]] virtual std::optional<StopReason> standing_fault(const PlcIo& /*io*/) const {
    return std::nullopt;
  }
  // The device's latched fault as text ("jam (fault 1)"), empty when none.
  [[nodiscard]] virtual std::string fault_text(const PlcIo& io) const = 0;
};

struct LogicContext {
  const GatewayConfig& config;
  const line::Layout& layout;
};

std::unique_ptr<DeviceLogic> make_conveyor(const LogicContext& context);
std::unique_ptr<DeviceLogic> make_transfer(const LogicContext& context);  // uploader, downloader
std::unique_ptr<DeviceLogic> make_legacy_robot(const LogicContext& context);

// "jam (PLC fault 1)"
std::string describe(line::FaultCode code);
// The device's latched fault (its `fault` input on) as text, empty when none.
std::string latched_fault(const PlcIo& io, std::uint16_t fault_input, std::uint16_t fault_code_register);
// "<what>: <fault> (PLC fault <n>)" as a stop reason with the PLC's code as its id.
StopReason plc_stop_reason(const std::string& what, line::FaultCode code);
// The operation's "box" is the one a tag reader (the input register `reader`)
// reads, the same on the last two polls.
bool box_read(const Operation& op, const PlcIo& io, std::uint16_t reader);
// An integer parameter of an operation within [lo, hi], or why not.
Result<std::int64_t> int_param(const Operation& op, std::string_view name, std::int64_t lo, std::int64_t hi);

}  // namespace sf::factory::gateway
