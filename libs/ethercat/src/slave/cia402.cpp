#include "sf/ethercat/slave/cia402.hpp"

#include <algorithm>
#include <cmath>

#include "sf/ethercat/sdo_abort_codes.hpp"

namespace sf::ethercat::slave {

namespace {

// Controlword commands (CiA 402 §6.2.1, Table 26): masks and values.
bool shutdown(std::uint16_t cw) {
  return (cw & 0x87U) == 0x06U;
}
bool switch_on(std::uint16_t cw) {
  return (cw & 0x8FU) == 0x07U;
}  // also "disable operation"
bool enable_operation(std::uint16_t cw) {
  return (cw & 0x8FU) == 0x0FU;
}
bool disable_voltage(std::uint16_t cw) {
  return (cw & 0x82U) == 0x00U;
}
bool quick_stop(std::uint16_t cw) {
  return (cw & 0x86U) == 0x02U;
}
constexpr std::uint16_t kFaultReset = 0x0080;

// Statusword bits (CiA 402 §6.2.2).
constexpr std::uint16_t kVoltageEnabled = 1U << 4;
constexpr std::uint16_t kRemote = 1U << 9;
constexpr std::uint16_t kTargetReached = 1U << 10;
constexpr std::uint16_t kInternalLimit = 1U << 11;
constexpr std::uint16_t kFollowsCommand = 1U << 12;  // CSP: target position used
constexpr std::uint16_t kFollowingError = 1U << 13;  // CSP

constexpr double kStandstill = 1e-6;  // counts/s

}  // namespace

const char* to_string(Cia402State s) {
  switch (s) {
    case Cia402State::NotReadyToSwitchOn:
      return "Not ready to switch on";
    case Cia402State::SwitchOnDisabled:
      return "Switch on disabled";
    case Cia402State::ReadyToSwitchOn:
      return "Ready to switch on";
    case Cia402State::SwitchedOn:
      return "Switched on";
    case Cia402State::OperationEnabled:
      return "Operation enabled";
    case Cia402State::QuickStopActive:
      return "Quick stop active";
    case Cia402State::FaultReactionActive:
      return "Fault reaction active";
    case Cia402State::Fault:
      return "Fault";
  }
  return "?";
}

Cia402Axis::Cia402Axis(ObjectDictionary& od, unsigned axis, AxisDefaults defaults)
    : base_(static_cast<std::uint16_t>(0x6000U + 0x800U * axis)), defaults_(defaults) {
  using DT = DataType;
  namespace a = access;
  auto var = [&](std::uint16_t profile, const char* name, DT type, std::uint16_t acc, std::uint64_t initial) {
    return &od.add_var(object(profile), name, type, acc, initial);
  };
  error_code_ = var(0x603F, "Error code", DT::Unsigned16, a::kRO | a::kTxPdo, 0);
  controlword_ = var(0x6040, "Controlword", DT::Unsigned16, a::kRW | a::kRxPdo, 0);
  statusword_ = var(0x6041, "Statusword", DT::Unsigned16, a::kRO | a::kTxPdo, 0);
  quick_stop_option_ = var(0x605A, "Quick stop option code", DT::Integer16, a::kRW, 2);
  mode_ = var(0x6060, "Modes of operation", DT::Integer8, a::kRW | a::kRxPdo,
              static_cast<std::uint8_t>(kModeCyclicSynchronousPosition));
  mode_display_ = var(0x6061, "Modes of operation display", DT::Integer8, a::kRO | a::kTxPdo,
                      static_cast<std::uint8_t>(kModeCyclicSynchronousPosition));
  demand_value_ = var(0x6062, "Position demand value", DT::Integer32, a::kRO | a::kTxPdo, 0);
  position_actual_ = var(0x6064, "Position actual value", DT::Integer32, a::kRO | a::kTxPdo, 0);
  following_window_ =
      var(0x6065, "Following error window", DT::Unsigned32, a::kRW, defaults.following_error_window);
  following_timeout_ =
      var(0x6066, "Following error time out", DT::Unsigned16, a::kRW, defaults.following_error_timeout_ms);
  velocity_actual_ = var(0x606C, "Velocity actual value", DT::Integer32, a::kRO | a::kTxPdo, 0);
  target_ = var(0x607A, "Target position", DT::Integer32, a::kRW | a::kRxPdo, 0);
  max_velocity_ = var(0x607F, "Max profile velocity", DT::Unsigned32, a::kRW, defaults.max_velocity);
  quick_stop_decel_ =
      var(0x6085, "Quick stop deceleration", DT::Unsigned32, a::kRW, defaults.quick_stop_deceleration);
  max_accel_ = var(0x60C5, "Max acceleration", DT::Unsigned32, a::kRW, defaults.max_acceleration);
  following_actual_ = var(0x60F4, "Following error actual value", DT::Integer32, a::kRO | a::kTxPdo, 0);
  var(0x6502, "Supported drive modes", DT::Unsigned32, a::kRO, 1U << 7U);  // bit 7: CSP
  // Only CSP (8) and "no mode" (0) are offered.
  od.find(object(0x6060))->set_validator([](const OdObject&, std::uint8_t, ByteSpan d) -> AbortCode {
    const auto mode = static_cast<std::int8_t>(d[0]);
    return mode == 0 || mode == kModeCyclicSynchronousPosition
               ? 0
               : static_cast<AbortCode>(SdoAbortCode::ValueRangeExceeded);
  });
  power_on();
}

void Cia402Axis::power_on() {
  state_ = Cia402State::NotReadyToSwitchOn;
  velocity_ = 0.0;
  demand_ = position_;
  following_time_ = 0.0;
  controlword_->set<std::uint16_t>(0);
  last_controlword_ = 0;
  error_code_->set<std::uint16_t>(0);
  target_->set<std::int32_t>(static_cast<std::int32_t>(std::llround(position_)));
  last_target_ = position_;
  // Initialisation done: transition 1, automatically.
  transition(Cia402State::SwitchOnDisabled);
  refresh_inputs();
}

void Cia402Axis::set_position(double counts) {
  position_ = counts;
  if (state_ != Cia402State::OperationEnabled) {
    demand_ = counts;
  }
  refresh_inputs();
}

void Cia402Axis::transition(Cia402State to) {
  if (to == Cia402State::OperationEnabled && state_ != Cia402State::OperationEnabled) {
    last_target_ = target_->get<std::int32_t>();
    demand_ = position_;
    following_time_ = 0.0;
  }
  state_ = to;
  refresh_inputs();
}

void Cia402Axis::fault(std::uint16_t error) {
  error_code_->set<std::uint16_t>(error);
  transition(Cia402State::FaultReactionActive);
}

void Cia402Axis::apply_controlword() {
  const std::uint16_t cw = controlword_->get<std::uint16_t>();
  const bool reset_edge = (cw & kFaultReset) != 0 && (last_controlword_ & kFaultReset) == 0;
  last_controlword_ = cw;
  switch (state_) {
    case Cia402State::NotReadyToSwitchOn:
    case Cia402State::FaultReactionActive:
      break;  // leave on their own
    case Cia402State::SwitchOnDisabled:
      if (shutdown(cw)) {
        transition(Cia402State::ReadyToSwitchOn);  // 2
      }
      break;
    case Cia402State::ReadyToSwitchOn:
      if (disable_voltage(cw) || quick_stop(cw)) {
        transition(Cia402State::SwitchOnDisabled);  // 7
      } else if (enable_operation(cw)) {
        transition(Cia402State::OperationEnabled);  // 3 + 4
      } else if (switch_on(cw)) {
        transition(Cia402State::SwitchedOn);  // 3
      }
      break;
    case Cia402State::SwitchedOn:
      if (disable_voltage(cw) || quick_stop(cw)) {
        transition(Cia402State::SwitchOnDisabled);  // 10
      } else if (shutdown(cw)) {
        transition(Cia402State::ReadyToSwitchOn);  // 6
      } else if (enable_operation(cw)) {
        transition(Cia402State::OperationEnabled);  // 4
      }
      break;
    case Cia402State::OperationEnabled:
      if (disable_voltage(cw)) {
        transition(Cia402State::SwitchOnDisabled);  // 9
      } else if (quick_stop(cw)) {
        transition(Cia402State::QuickStopActive);  // 11
      } else if (shutdown(cw)) {
        transition(Cia402State::ReadyToSwitchOn);  // 8
      } else if (switch_on(cw)) {
        transition(Cia402State::SwitchedOn);  // 5
      }
      break;
    case Cia402State::QuickStopActive:
      if (disable_voltage(cw)) {
        transition(Cia402State::SwitchOnDisabled);  // 12
      } else if (enable_operation(cw) && quick_stop_option_->get<std::int16_t>() >= 5) {
        transition(Cia402State::OperationEnabled);  // 16, only for options 5..8
      }
      break;
    case Cia402State::Fault:
      if (reset_edge) {
        error_code_->set<std::uint16_t>(0);
        transition(Cia402State::SwitchOnDisabled);  // 15
      }
      break;
  }
}

void Cia402Axis::step(double dt) {
  if (dt <= 0.0) {
    refresh_inputs();
    return;
  }
  switch (state_) {
    case Cia402State::OperationEnabled:
      if (mode_->get<std::int8_t>() == kModeCyclicSynchronousPosition) {
        demand_ = target_->get<std::int32_t>();
        move(dt);
      } else {
        decelerate(dt, max_accel_->get<std::uint32_t>());
        demand_ = position_;
      }
      supervise(dt);
      break;
    case Cia402State::QuickStopActive:
      decelerate(dt, quick_stop_decel_->get<std::uint32_t>());
      demand_ = position_;
      // Quick stop option 1..3: after the stop, to Switch on disabled (12).
      if (std::fabs(velocity_) < kStandstill && quick_stop_option_->get<std::int16_t>() < 5) {
        transition(Cia402State::SwitchOnDisabled);
      }
      break;
    case Cia402State::FaultReactionActive:
      decelerate(dt, quick_stop_decel_->get<std::uint32_t>());
      demand_ = position_;
      if (std::fabs(velocity_) < kStandstill) {
        transition(Cia402State::Fault);  // 14
      }
      break;
    default:
      velocity_ = 0.0;  // power stage off: the motor stands
      demand_ = position_;
      break;
  }
  refresh_inputs();
}

void Cia402Axis::move(double dt) {
  const double a = std::max<double>(max_accel_->get<std::uint32_t>(), 1.0);
  const double vmax = max_velocity_->get<std::uint32_t>();
  const double error = demand_ - position_;
  const double feed_forward = (demand_ - last_target_) / dt;
  last_target_ = demand_;
  // Land on the demand this cycle, but never faster than allows stopping on
  // it (relative to a moving target) within the acceleration limit.
  double wanted = error / dt;
  const double braking = feed_forward + std::copysign(std::sqrt(2.0 * a * std::fabs(error)), error);
  if (std::fabs(wanted) > std::fabs(braking) && std::signbit(wanted) == std::signbit(braking)) {
    wanted = braking;
  }
  double v = std::clamp(wanted, velocity_ - a * dt, velocity_ + a * dt);
  v = std::clamp(v, -vmax, vmax);
  limited_ = std::fabs(v - wanted) > 1e-9;
  velocity_ = v;
  position_ += v * dt;
}

void Cia402Axis::decelerate(double dt, double deceleration) {
  const double step = std::max(deceleration, 1.0) * dt;
  velocity_ = std::fabs(velocity_) <= step ? 0.0 : velocity_ - std::copysign(step, velocity_);
  position_ += velocity_ * dt;
  limited_ = false;
}

void Cia402Axis::supervise(double dt) {
  const double window = following_window_->get<std::uint32_t>();
  if (std::fabs(demand_ - position_) <= window) {
    following_time_ = 0.0;
    return;
  }
  following_time_ += dt;
  if (following_time_ * 1000.0 > following_timeout_->get<std::uint16_t>()) {
    fault(kErrorFollowing);
  }
}

void Cia402Axis::communication_lost() {
  if (state_ == Cia402State::OperationEnabled || state_ == Cia402State::QuickStopActive) {
    fault(kErrorCommunication);
  }
}

std::uint16_t Cia402Axis::statusword() const {
  std::uint16_t sw = kRemote;
  switch (state_) {
    case Cia402State::NotReadyToSwitchOn:
      break;
    case Cia402State::SwitchOnDisabled:
      sw |= 0x0040;
      break;
    case Cia402State::ReadyToSwitchOn:
      sw |= 0x0021;
      break;
    case Cia402State::SwitchedOn:
      sw |= 0x0023 | kVoltageEnabled;
      break;
    case Cia402State::OperationEnabled:
      sw |= 0x0027 | kVoltageEnabled | kFollowsCommand;
      if (std::fabs(target_->get<std::int32_t>() - position_) <= 0.5) {
        sw |= kTargetReached;
      }
      if (limited_) {
        sw |= kInternalLimit;
      }
      if (std::fabs(demand_ - position_) > following_window_->get<std::uint32_t>()) {
        sw |= kFollowingError;
      }
      break;
    case Cia402State::QuickStopActive:
      sw |= 0x0007 | kVoltageEnabled;
      break;
    case Cia402State::FaultReactionActive:
      sw |= 0x000F | kVoltageEnabled;
      break;
    case Cia402State::Fault:
      sw |= 0x0008;
      if (error_code_->get<std::uint16_t>() == kErrorFollowing) {
        sw |= kFollowingError;
      }
      break;
  }
  return sw;
}

void Cia402Axis::refresh_inputs() {
  auto to_i32 = [](double v) {
    return static_cast<std::int32_t>(static_cast<std::int64_t>(std::llround(v)));
  };
  statusword_->set<std::uint16_t>(statusword());
  mode_display_->set<std::int8_t>(mode_->get<std::int8_t>());
  demand_value_->set<std::int32_t>(to_i32(demand_));
  position_actual_->set<std::int32_t>(to_i32(position_));
  velocity_actual_->set<std::int32_t>(to_i32(velocity_));
  following_actual_->set<std::int32_t>(to_i32(demand_ - position_));
}

}  // namespace sf::ethercat::slave
