// CiA 402 device control (IEC 61800-7-201 §6.2.3): statusword decoding,
// the controlword walk through the power drive system state machine, and a
// per-cycle position target in CSP mode.
#include "sf/ethercat/master/cia402.hpp"

#include <fmt/format.h>

#include "sf/ethercat/master/master.hpp"

namespace sf::ethercat::master {
namespace cia402 {

std::string_view to_string(State s) {
  switch (s) {
    case State::NotReadyToSwitchOn:
      return "not ready to switch on";
    case State::SwitchOnDisabled:
      return "switch on disabled";
    case State::ReadyToSwitchOn:
      return "ready to switch on";
    case State::SwitchedOn:
      return "switched on";
    case State::OperationEnabled:
      return "operation enabled";
    case State::QuickStopActive:
      return "quick stop active";
    case State::FaultReactionActive:
      return "fault reaction active";
    case State::Fault:
      return "fault";
  }
  return "?";
}

State state_from_statusword(std::uint16_t sw) {
  // IEC 61800-7-201 Table 3: bits 6,5,3,2,1,0 (mask 0x6F) or 6,3,2,1,0 (0x4F).
  if ((sw & 0x4FU) == 0x00U) {
    return State::NotReadyToSwitchOn;
  }
  if ((sw & 0x4FU) == 0x40U) {
    return State::SwitchOnDisabled;
  }
  if ((sw & 0x6FU) == 0x21U) {
    return State::ReadyToSwitchOn;
  }
  if ((sw & 0x6FU) == 0x23U) {
    return State::SwitchedOn;
  }
  if ((sw & 0x6FU) == 0x27U) {
    return State::OperationEnabled;
  }
  if ((sw & 0x6FU) == 0x07U) {
    return State::QuickStopActive;
  }
  if ((sw & 0x4FU) == 0x0FU) {
    return State::FaultReactionActive;
  }
  if ((sw & 0x4FU) == 0x08U) {
    return State::Fault;
  }
  return State::NotReadyToSwitchOn;
}

std::uint16_t next_controlword(State state, bool enable) {
  if (!enable) {
    return kDisableVoltage;
  }
  switch (state) {
    case State::SwitchOnDisabled:
      return kShutdown;  // transition 2
    case State::ReadyToSwitchOn:
      return kSwitchOn;  // transition 3
    case State::SwitchedOn:
    case State::OperationEnabled:
      return kEnableOperation;        // transition 4, then hold
    case State::QuickStopActive:      // transition 12, then up again
    case State::NotReadyToSwitchOn:   // wait
    case State::FaultReactionActive:  // wait
    case State::Fault:                // wait: a fault needs fault_reset()
      return kDisableVoltage;
  }
  return kDisableVoltage;
}

}  // namespace cia402

namespace {

constexpr std::uint16_t kControlword = 0x6040;
constexpr std::uint16_t kStatusword = 0x6041;
constexpr std::uint16_t kModesOfOperation = 0x6060;
constexpr std::uint16_t kPositionActual = 0x6064;
constexpr std::uint16_t kVelocityActual = 0x606C;
constexpr std::uint16_t kTargetPosition = 0x607A;
constexpr std::uint16_t kAxisStride = 0x800;

}  // namespace

Result<Cia402Axis> Cia402Axis::attach(Master& master, std::size_t position, unsigned axis) {
  if (position >= master.slave_count()) {
    return make_error(Errc::invalid_argument, fmt::format("no slave at position {}", position));
  }
  if (axis >= 8) {
    return make_error(Errc::invalid_argument, fmt::format("axis {}: CiA 402 allows 8 axes per slave", axis));
  }
  Cia402Axis a(master, position, axis);
  const auto view = master.slave(position);
  const auto at = [&](std::uint16_t index) { return static_cast<std::uint16_t>(index + kAxisStride * axis); };
  auto resolve = [&](std::uint16_t index, EntryRef& out) -> Status {
    auto e = view.entry(at(index), 0);
    if (!e) {
      return e.error().with_context(fmt::format("slave {} axis {}", position, axis));
    }
    out = *e;
    return {};
  };
  SF_TRY(resolve(kControlword, a.controlword_));
  SF_TRY(resolve(kStatusword, a.statusword_));
  SF_TRY(resolve(kTargetPosition, a.target_position_));
  SF_TRY(resolve(kPositionActual, a.actual_position_));
  if (auto v = view.entry(at(kVelocityActual), 0)) {
    a.actual_velocity_ = *v;
  }
  if (auto m = view.entry(at(kModesOfOperation), 0); m && m->direction == PdoDirection::output) {
    a.mode_ = *m;
  } else if (master.slave_info(position).mailbox.coe()) {
    SF_TRY(master.sdo_write<std::int8_t>(position, at(kModesOfOperation), 0,
                                         cia402::kModeCyclicSynchronousPosition));
  }
  a.target_ = a.actual_position();
  return a;
}

SlaveView Cia402Axis::view() const {
  return master_->slave(position_);
}

std::uint16_t Cia402Axis::statusword() const {
  return view().get<std::uint16_t>(statusword_);
}
std::uint16_t Cia402Axis::controlword() const {
  return view().get<std::uint16_t>(controlword_);
}
std::int32_t Cia402Axis::actual_position() const {
  return view().get<std::int32_t>(actual_position_);
}
std::int32_t Cia402Axis::actual_velocity() const {
  return actual_velocity_ ? view().get<std::int32_t>(*actual_velocity_) : 0;
}

void Cia402Axis::set_target_position(std::int32_t position) {
  trajectory_.clear();
  next_point_ = 0;
  target_ = position;
}

void Cia402Axis::follow(std::span<const std::int32_t> trajectory) {
  trajectory_.assign(trajectory.begin(), trajectory.end());
  next_point_ = 0;
}

std::uint16_t Cia402Axis::command_for(cia402::State s) {
  if (s == cia402::State::Fault && fault_reset_requested_) {
    // Bit 7 low for one cycle, then high: the drive acts on the edge.
    fault_reset_edge_ = !fault_reset_edge_;
    return fault_reset_edge_ ? cia402::kDisableVoltage : cia402::kFaultReset;
  }
  if (s != cia402::State::Fault) {
    fault_reset_requested_ = false;
    fault_reset_edge_ = false;
  }
  return cia402::next_controlword(s, want_enabled_);
}

void Cia402Axis::update() {
  auto v = view();
  const auto s = state();
  if (s != cia402::State::OperationEnabled) {
    // Not following: hold where the axis is, so enabling causes no jump.
    target_ = actual_position();
    next_point_ = std::min(next_point_, trajectory_.size());
  } else if (next_point_ < trajectory_.size()) {
    target_ = trajectory_[next_point_++];
  }
  v.set<std::uint16_t>(controlword_, command_for(s));
  v.set<std::int32_t>(target_position_, target_);
  if (mode_) {
    v.set<std::int8_t>(*mode_, cia402::kModeCyclicSynchronousPosition);
  }
}

}  // namespace sf::ethercat::master
