// The EtherCAT state machine from the master's side (ETG.1000.6 §6.4.1,
// ET1100 datasheet II §4): request a state in AL control (0x0120), wait for AL
// status (0x0130) to follow, and on refusal report the AL status code
// (0x0134) with its text. States are walked one at a time upwards
// (INIT → PREOP → SAFEOP → OP), each step preceded by what it needs.
#include <algorithm>
#include <array>

#include <fmt/format.h>

#include "poll.hpp"
#include "sf/ethercat/al_status_codes.hpp"
#include "sf/ethercat/master/master.hpp"

namespace sf::ethercat::master {
namespace {

// The next state to request on the way from `from` to `to`: up one state at
// a time; down in one step; BOOT only from and to INIT (ETG.1000.6 §6.4.1).
AlState next_toward(AlState from, AlState to) {
  if (to == AlState::Bootstrap || from == AlState::Bootstrap) {
    return from == AlState::Init ? to : AlState::Init;
  }
  if (rank(to) <= rank(from)) {
    return to;
  }
  switch (from) {
    case AlState::Init:
      return AlState::PreOp;
    case AlState::PreOp:
      return AlState::SafeOp;
    default:
      return AlState::Op;
  }
}

}  // namespace

std::string describe_al_status_code(std::uint16_t code) {
  return fmt::format("0x{:04X} {}", code, describe(static_cast<AlStatusCode>(code)));
}

Result<AlStatus> Master::read_state(std::size_t position) {
  if (position >= slaves_.size()) {
    return make_error(Errc::invalid_argument, fmt::format("no slave at position {}", position));
  }
  auto& s = slaves_[position];
  std::array<std::uint8_t, 6> buf{};  // 0x0130 status, 0x0132 reserved, 0x0134 code
  SF_TRY(bus_.read_one(Command::FPRD, s.station, reg::kAlStatus, buf));
  s.al_status = AlStatus::decode(load_le<std::uint16_t>(buf.data()));
  s.al_status_code = load_le<std::uint16_t>(&buf[4]);
  return s.al_status;
}

Status Master::acknowledge_error(std::size_t position) {
  auto st = read_state(position);
  if (!st) {
    return st.error();
  }
  // Acknowledge by requesting the current state with the error bit set
  // (ETG.1000.6 §6.4.1.3).
  const auto current = st->state().value_or(AlState::Init);
  return bus_.fpwr<std::uint16_t>(slaves_[position].station, reg::kAlControl,
                                  AlControl::of(current, true).encode());
}

Error Master::state_error(std::size_t position, AlState target, const AlStatus& status) {
  const auto& s = slaves_[position];
  std::string text = fmt::format("slave {} ({}): {} requested, slave is in {}", position, s.name(),
                                 to_string(target), status.to_string());
  if (status.error || s.al_status_code != 0) {
    text += fmt::format(", AL status code {}", describe_al_status_code(s.al_status_code));
  }
  return make_error(Errc::remote, std::move(text));
}

Status Master::wait_state(std::size_t position, AlState target) {
  const bool op = target == AlState::Op;
  Status failure;
  auto reached = [&]() -> Result<bool> {
    if (op && process_data_configured_) {
      // A slave enters OP only with valid outputs: keep the cycle running.
      (void)exchange();
    }
    auto st = read_state(position);
    if (!st) {
      return st.error();
    }
    if (st->state() == target && !st->error) {
      return true;
    }
    if (st->error) {
      failure = state_error(position, target, *st);
      return failure.error();
    }
    return false;
  };
  auto st = detail::poll_until(clock_, options_.state_timeout, options_.poll_interval,
                               fmt::format("slave {} to {}", position, to_string(target)), reached);
  if (!st && st.error().code == Errc::timeout) {
    return state_error(position, target, slaves_[position].al_status)
        .with_context(fmt::format(
            "timeout after {} ms",
            std::chrono::duration_cast<std::chrono::milliseconds>(options_.state_timeout).count()));
  }
  return st;
}

Status Master::before_transition(std::size_t position, AlState from, AlState to) {
  if (to == AlState::PreOp && rank(from) < rank(AlState::PreOp)) {
    return configure_mailbox(position);
  }
  if (to == AlState::SafeOp && !process_data_configured_) {
    return configure_process_data();
  }
  return {};
}

Status Master::step_state(std::size_t position, AlState next) {
  auto& s = slaves_[position];
  const auto from = s.al_status.state().value_or(AlState::Init);
  SF_TRY(before_transition(position, from, next));
  // Requesting with the acknowledge bit clears an error left from before.
  SF_TRY(
      bus_.fpwr<std::uint16_t>(s.station, reg::kAlControl, AlControl::of(next, s.al_status.error).encode()));
  return wait_state(position, next);
}

Status Master::request_state(std::size_t position, AlState target) {
  if (position >= slaves_.size()) {
    return make_error(Errc::invalid_argument, fmt::format("no slave at position {}", position));
  }
  std::lock_guard lock(control_mutex_);
  // At most BOOT → INIT → PREOP → SAFEOP → OP.
  for (int steps = 0;; ++steps) {
    auto st = read_state(position);
    if (!st) {
      return st.error();
    }
    const auto current = st->state().value_or(AlState::Init);
    if (current == target && !st->error) {
      return {};
    }
    if (steps == 4) {
      return state_error(position, target, *st);
    }
    SF_TRY(step_state(position, next_toward(current, target)));
  }
}

Status Master::request_state(AlState target) {
  std::lock_guard lock(control_mutex_);
  if (slaves_.empty()) {
    return make_error(Errc::state, "no slaves: scan first");
  }
  target_state_ = target;
  // Up: all slaves together, one state at a time, so that what a step needs
  // from the whole segment (the process image before SAFEOP) is in place.
  for (const auto step : {AlState::PreOp, AlState::SafeOp, AlState::Op}) {
    if (rank(step) > rank(target)) {
      break;
    }
    for (std::size_t p = 0; p < slaves_.size(); ++p) {
      auto st = read_state(p);
      if (!st) {
        return st.error();
      }
      if (rank(st->state().value_or(AlState::Init)) < rank(step) || st->error) {
        SF_TRY(request_state(p, step));
      }
    }
  }
  // Down (e.g. OP → PREOP) is one request per slave.
  for (std::size_t p = 0; p < slaves_.size(); ++p) {
    SF_TRY(request_state(p, target));
  }
  return {};
}

Status Master::bring_up(AlState target) {
  auto n = scan();
  if (!n) {
    return n.error();
  }
  if (*n == 0) {
    return make_error(Errc::not_found, "no slaves found");
  }
  SF_TRY(request_state(AlState::PreOp));
  if (rank(target) >= rank(AlState::SafeOp)) {
    SF_TRY(configure_process_data());
    if (options_.distributed_clocks) {
      SF_TRY(configure_dc());
    }
  }
  return request_state(target);
}

}  // namespace sf::ethercat::master
