// PlcDevice, the job handshake and the conveyor PLC (plc.hpp).
#include "sf/plant/plc.hpp"

#include <algorithm>
#include <cmath>
#include <mutex>

namespace sf::plant {

namespace {

modbus::RegisterBank make_bank(const modbus::BankLayout& layout) {
  auto bank = modbus::RegisterBank::create(layout);
  // The layouts are the constants of registers.cpp: a failure is a programming error.
  if (!bank) {
    std::abort();
  }
  return std::move(*bank);
}

std::uint16_t mm(double metres) {
  return static_cast<std::uint16_t>(std::lround(std::clamp(metres, 0.0, 65.535) * 1000.0));
}

}  // namespace

PlcDevice::PlcDevice(std::string name, modbus::BankLayout layout)
    : bank_(make_bank(layout)), name_(std::move(name)) {}

void PlcDevice::scan(World& world, double dt) {
  std::lock_guard lock(mutex());
  run(world, dt);
}

bool JobHandshake::scan(const modbus::RegisterBank& bank) {
  const bool start = bank.coil(transfer_plc::kStart);
  const bool reset = bank.coil(transfer_plc::kFaultReset);
  const bool start_edge = start && !last_start_;
  const bool reset_edge = reset && !last_reset_;
  last_start_ = start;
  last_reset_ = reset;
  if (phase_ == Phase::fault && reset_edge) {
    phase_ = Phase::ready;
    code_ = FaultCode::none;
    return false;
  }
  if (phase_ == Phase::done && !start) {
    phase_ = Phase::ready;
  }
  if (phase_ == Phase::ready && start_edge) {
    phase_ = Phase::busy;
    return true;
  }
  return false;
}

void JobHandshake::publish(modbus::RegisterBank& bank) const {
  bank.set_discrete_input(transfer_plc::kReady, phase_ == Phase::ready);
  bank.set_discrete_input(transfer_plc::kBusy, phase_ == Phase::busy);
  bank.set_discrete_input(transfer_plc::kDone, phase_ == Phase::done);
  bank.set_discrete_input(transfer_plc::kFault, phase_ == Phase::fault);
}

// --- conveyor --------------------------------------------------------------

ConveyorPlc::ConveyorPlc(const World& world, std::size_t belt)
    : PlcDevice(world.layout().belts.at(belt).name, conveyor_bank_layout()), belt_(belt) {
  bank_.set_input_register(conveyor_plc::kStationCount,
                           static_cast<std::uint16_t>(world.layout().belts[belt].stations.size()));
}

void ConveyorPlc::run(World& world, double /*dt*/) {
  using namespace conveyor_plc;
  const BeltSpec& spec = world.layout().belts[belt_];
  const bool reset = bank_.coil(kFaultReset);
  if (world.belt(belt_).jammed) {
    fault_code_ = FaultCode::jam;  // latched: the motor stays off until a reset after the jam is gone
  } else if (reset && !last_reset_) {
    fault_code_ = FaultCode::none;
  }
  last_reset_ = reset;
  const bool run = bank_.coil(kMotorRun) && fault_code_ == FaultCode::none;
  world.set_motor(belt_, run, bank_.coil(kReverse));
  const std::uint16_t setpoint = bank_.holding_register(kSpeedSetpoint);
  world.set_speed(belt_, setpoint == 0 ? spec.speed_mps : setpoint / 1000.0);
  world.set_exit(belt_, bank_.coil(kDivert) ? 1 : 0);
  for (std::size_t k = 0; k < spec.stations.size(); ++k) {
    world.set_stopper(belt_, k, bank_.coil(static_cast<std::uint16_t>(kStopper + k)));
  }
  publish(world);
}

void ConveyorPlc::publish(const World& world) {
  using namespace conveyor_plc;
  const BeltState& state = world.belt(belt_);
  bank_.set_discrete_input(kEntryEye, world.entry_eye(belt_));
  bank_.set_discrete_input(kExitEye, world.exit_eye(belt_));
  bank_.set_discrete_input(kJam, state.jammed);
  bank_.set_discrete_input(kRunning, state.motor);
  bank_.set_discrete_input(kFault, fault_code_ != FaultCode::none);
  bank_.set_input_register(kSpeed, state.motor ? mm(state.speed_mps) : 0);
  bank_.set_input_register(kFaultCode, static_cast<std::uint16_t>(fault_code_));
  bank_.set_input_register(kOdometer,
                           static_cast<std::uint16_t>(static_cast<std::uint64_t>(state.odometer_m) & 0xFFFF));
  const auto& stations = world.layout().belts[belt_].stations;
  for (std::size_t k = 0; k < stations.size(); ++k) {
    const auto offset = static_cast<std::uint16_t>(k);
    bank_.set_discrete_input(static_cast<std::uint16_t>(kStationEye + offset), world.station_eye(belt_, k));
    bank_.set_input_register(static_cast<std::uint16_t>(kStationBox + offset), world.tag_reading(belt_, k));
  }
}

}  // namespace sf::plant
