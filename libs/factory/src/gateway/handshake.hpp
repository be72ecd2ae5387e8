// Handshake: the job handshake of the job-driven devices (registers.hpp:
// uploader, downloader, legacy robots) as a state machine across polls —
// the job's registers and `start`; `busy`, then `done` or `fault` with its
// code; `start` cleared (and a fault reset), `ready` again. The coils and
// discrete inputs it uses sit at the same addresses in both maps.
#pragma once

#include <cstdint>
#include <functional>
#include <optional>

#include "plc_io.hpp"
#include "sf/line/registers.hpp"

namespace sf::factory::gateway {

static_assert(line::transfer_plc::kStart == line::robot_controller::kStart &&
              line::transfer_plc::kFaultReset == line::robot_controller::kFaultReset &&
              line::transfer_plc::kReady == line::robot_controller::kReady &&
              line::transfer_plc::kBusy == line::robot_controller::kBusy &&
              line::transfer_plc::kDone == line::robot_controller::kDone &&
              line::transfer_plc::kFault == line::robot_controller::kFault);

class Handshake {
 public:
  // `fault_code` is the input register of the device's map that holds it.
  explicit Handshake(std::uint16_t fault_code) : fault_code_(fault_code) {}

  // Starts a job when the device is ready: `write` puts the job's registers, then start is
  // set. False while the device is not ready yet (a latched fault is reset meanwhile, a stale
  // done acknowledged).
  bool start(PlcIo& io, const std::function<void(PlcIo&)>& write);
  // Follows the started job: its fault code (none: done) once the device is ready again.
  std::optional<line::FaultCode> follow(PlcIo& io);
  [[nodiscard]] bool running() const { return phase_ != Phase::idle; }
  // The job is dropped: start cleared (the device finishes on its own and becomes ready).
  void abandon(PlcIo& io);
  // Resetting: start cleared, a latched fault reset; true once the device is ready.
  bool reset(PlcIo& io);

 private:
  enum class Phase : std::uint8_t { idle, requested, clearing };
  // A rising edge of fault_reset every other poll while the device shows a fault.
  static void pulse_fault_reset(PlcIo& io);

  std::uint16_t fault_code_;
  Phase phase_ = Phase::idle;
  line::FaultCode code_ = line::FaultCode::none;
};

}  // namespace sf::factory::gateway
