// PackMLUnit (packml.hpp): OPC 30050 §6 / ISA-TR88.00.02 state model.
#include "sf/factory/packml.hpp"

#include <fmt/format.h>

namespace sf::factory {

namespace {

using S = PackMLState;
using C = PackMLCommand;

// Where a command leads from a state; Undefined when the state does not accept it.
PackMLState target(PackMLState s, PackMLCommand c) {
  switch (c) {
    case C::Reset:
      return s == S::Stopped || s == S::Complete ? S::Resetting : S::Undefined;
    case C::Start:
      return s == S::Idle ? S::Starting : S::Undefined;
    case C::Stop:
      return s == S::Stopped || s == S::Stopping || s == S::Aborting || s == S::Aborted || s == S::Clearing
                 ? S::Undefined
                 : S::Stopping;
    case C::Hold:
      return s == S::Execute || s == S::Suspended ? S::Holding : S::Undefined;
    case C::Unhold:
      return s == S::Held ? S::Unholding : S::Undefined;
    case C::Suspend:
      return s == S::Execute ? S::Suspending : S::Undefined;
    case C::Unsuspend:
      return s == S::Suspended ? S::Unsuspending : S::Undefined;
    case C::Abort:
      return s == S::Aborting || s == S::Aborted ? S::Undefined : S::Aborting;
    case C::Clear:
      return s == S::Aborted ? S::Clearing : S::Undefined;
  }
  return S::Undefined;
}

// The state an acting state (and Execute) leads to when its work is done.
PackMLState after(PackMLState s) {
  switch (s) {
    case S::Resetting:
      return S::Idle;
    case S::Starting:
    case S::Unholding:
    case S::Unsuspending:
      return S::Execute;
    case S::Execute:
      return S::Completing;
    case S::Completing:
      return S::Complete;
    case S::Holding:
      return S::Held;
    case S::Suspending:
      return S::Suspended;
    case S::Stopping:
    case S::Clearing:
      return S::Stopped;
    case S::Aborting:
      return S::Aborted;
    default:
      return S::Undefined;
  }
}

}  // namespace

std::string_view to_string(PackMLState state) {
  static constexpr std::string_view kNames[] = {
      "Undefined", "Clearing",   "Stopped",      "Starting",  "Idle",       "Suspended",
      "Execute",   "Stopping",   "Aborting",     "Aborted",   "Holding",    "Held",
      "Unholding", "Suspending", "Unsuspending", "Resetting", "Completing", "Complete"};
  const auto i = static_cast<std::size_t>(state);
  return i < std::size(kNames) ? kNames[i] : "Undefined";
}

std::string_view to_string(PackMLCommand command) {
  static constexpr std::string_view kNames[] = {"Undefined", "Reset",   "Start",     "Stop",  "Hold",
                                                "Unhold",    "Suspend", "Unsuspend", "Abort", "Clear"};
  const auto i = static_cast<std::size_t>(command);
  return i < std::size(kNames) ? kNames[i] : "Undefined";
}

std::string_view to_string(PackMLMode mode) {
  switch (mode) {
    case PackMLMode::Production:
      return "Production";
    case PackMLMode::Maintenance:
      return "Maintenance";
    case PackMLMode::Manual:
      return "Manual";
  }
  return "Undefined";
}

PackMLUnit::PackMLUnit(const Clock& clock, PackMLState initial)
    : clock_(&clock), state_(initial), entered_(clock.now()) {}

bool PackMLUnit::acting(PackMLState state) {
  return after(state) != S::Undefined && state != S::Execute;
}

bool PackMLUnit::advance_to_execute() {
  if (state_ == PackMLState::Stopped) {
    (void)command(PackMLCommand::Reset);
  } else if (state_ == PackMLState::Idle) {
    (void)command(PackMLCommand::Start);
  }
  return state_ == PackMLState::Execute;
}

bool PackMLUnit::accepts(PackMLCommand command) const {
  return target(state_, command) != S::Undefined;
}

Status PackMLUnit::command(PackMLCommand command, std::optional<StopReason> why) {
  const PackMLState next = target(state_, command);
  if (next == S::Undefined) {
    return make_error(Errc::state,
                      fmt::format("{} is not allowed in {}", to_string(command), to_string(state_)));
  }
  if (why && (command == C::Stop || command == C::Hold || command == C::Abort)) {
    why->at = clock_->utc_now();
    totals_.stop_reason = std::move(why);
  }
  enter(next);
  return {};
}

Status PackMLUnit::state_complete() {
  const PackMLState next = after(state_);
  if (next == S::Undefined) {
    return make_error(Errc::state, fmt::format("{} has no work to complete", to_string(state_)));
  }
  enter(next);
  return {};
}

void PackMLUnit::fault(StopReason why) {
  if (state_ == S::Aborting || state_ == S::Aborted) {
    return;
  }
  why.at = clock_->utc_now();
  totals_.stop_reason = std::move(why);
  enter(S::Aborting);
}

Status PackMLUnit::set_mode(PackMLMode mode) {
  if (state_ != S::Stopped && state_ != S::Idle && state_ != S::Aborted) {
    return make_error(Errc::state, fmt::format("the mode changes in Stopped, Idle or Aborted, not in {}",
                                               to_string(state_)));
  }
  mode_ = mode;
  return {};
}

void PackMLUnit::count(bool good) {
  ++totals_.produced;
  if (!good) {
    ++totals_.defective;
  }
}

void PackMLUnit::enter(PackMLState next) {
  const auto now = clock_->now();
  totals_.time_in_state[static_cast<std::size_t>(state_)] += now - entered_;
  entered_ = now;
  state_ = next;
}

PackMLStatus PackMLUnit::status() const {
  PackMLStatus s = totals_;
  s.state = state_;
  s.mode = mode_;
  s.state_current_time = clock_->now() - entered_;
  s.time_in_state[static_cast<std::size_t>(state_)] += s.state_current_time;
  return s;
}

std::optional<StopReason> operator_stop_reason(PackMLCommand command) {
  if (command != PackMLCommand::Stop && command != PackMLCommand::Hold && command != PackMLCommand::Abort) {
    return std::nullopt;
  }
  return StopReason{kStopOperator, fmt::format("operator: {}", to_string(command)), {}};
}

void PackMLUnit::run(UnitWork& work) {
  switch (state_) {
    case S::Execute:
      work.execute();
      return;
    case S::Resetting:
    case S::Clearing:
      if (state_ == S::Resetting ? work.reset() : work.clear()) {
        (void)state_complete();
      }
      return;
    case S::Starting:
    case S::Unholding:
    case S::Unsuspending:
    case S::Completing:
      (void)state_complete();
      return;
    case S::Holding:
    case S::Suspending:
    case S::Stopping:
      if (work.wind_down()) {
        if (state_ == S::Stopping) {
          work.stopped();
        }
        (void)state_complete();
      }
      return;
    case S::Aborting:
      work.abort();
      (void)state_complete();
      return;
    default:
      work.wait();
      return;
  }
}

}  // namespace sf::factory
