// The job handshake across polls (handshake.hpp).
#include "handshake.hpp"

namespace sf::factory::gateway {

namespace hs = line::transfer_plc;  // the handshake's addresses, the same in both maps

void Handshake::pulse_fault_reset(PlcIo& io) {
  io.write_coil(hs::kFaultReset, !io.coil(hs::kFaultReset));
}

bool Handshake::start(PlcIo& io, const std::function<void(PlcIo&)>& write) {
  if (io.input(hs::kFault)) {
    io.ensure_coil(hs::kStart, false);
    pulse_fault_reset(io);
    return false;
  }
  io.ensure_coil(hs::kFaultReset, false);
  if (io.input(hs::kDone) || io.coil(hs::kStart)) {
    io.ensure_coil(hs::kStart, false);  // a job of before: acknowledge it first
    return false;
  }
  if (!io.input(hs::kReady)) {
    return false;  // busy with a job of before (abandoned), or not yet up
  }
  write(io);
  io.write_coil(hs::kStart, true);
  if (io.write_failed()) {
    return false;  // tried again at the next poll
  }
  phase_ = Phase::requested;
  code_ = line::FaultCode::none;
  return true;
}

std::optional<line::FaultCode> Handshake::follow(PlcIo& io) {
  switch (phase_) {
    case Phase::idle:
      return std::nullopt;
    case Phase::requested:
      if (io.input(hs::kDone)) {
        code_ = line::FaultCode::none;
      } else if (io.input(hs::kFault)) {
        code_ = static_cast<line::FaultCode>(io.input_register(fault_code_));
        io.write_coil(hs::kFaultReset, true);
      } else {
        return std::nullopt;
      }
      io.write_coil(hs::kStart, false);
      phase_ = Phase::clearing;
      return std::nullopt;
    case Phase::clearing:
      io.ensure_coil(hs::kStart, false);  // again, should the first write have failed
      if (io.input(hs::kFault)) {
        pulse_fault_reset(io);
        return std::nullopt;
      }
      io.ensure_coil(hs::kFaultReset, false);
      if (!io.input(hs::kReady)) {
        return std::nullopt;
      }
      phase_ = Phase::idle;
      return code_;
  }
  return std::nullopt;
}

void Handshake::abandon(PlcIo& io) {
  io.ensure_coil(hs::kStart, false);
  phase_ = Phase::idle;
}

bool Handshake::reset(PlcIo& io) {
  abandon(io);
  if (io.input(hs::kFault)) {
    pulse_fault_reset(io);
    return false;
  }
  io.ensure_coil(hs::kFaultReset, false);
  return io.input(hs::kReady);
}

}  // namespace sf::factory::gateway
