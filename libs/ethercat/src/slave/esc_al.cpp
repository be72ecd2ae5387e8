// The EtherCAT state machine as the slave firmware runs it (ETG.1000.6 §6.4,
// ET1100 datasheet section I §12 "AL control/status"): requested states from
// AL control 0x0120, current state, error indicator and AL status code in
// 0x0130/0x0134, the SyncManager checks of each transition, and the
// process-data watchdog (section I §8.2, registers 0x0400–0x0443).
#include "esc_core.hpp"
#include "sf/ethercat/al_status_codes.hpp"

namespace sf::ethercat::slave::detail {

namespace {

constexpr std::uint16_t code(AlStatusCode c) {
  return static_cast<std::uint16_t>(c);
}

constexpr std::size_t kMinMailboxSize = kSdoInitiateOverhead;  // header + CoE + SDO initiate
constexpr std::size_t kMaxMailboxSize = 1024;

}  // namespace

void EscCore::on_al_control() {
  const AlControl control = AlControl::decode(mem_.get<std::uint16_t>(reg::kAlControl));
  op_pending_ = false;
  id_requested_ = control.request_id;
  if (al_error_ && control.acknowledge) {
    al_error_ = false;
    al_code_ = 0;
  }
  const auto requested = control.state();
  if (!requested) {
    refuse(code(AlStatusCode::UnknownRequestedState));
    return;
  }
  // With the error indicator set, only a lower state is accepted until the
  // master acknowledges (ETG.1000.6 §6.4.1.2).
  if (*requested == state_ || (al_error_ && rank(*requested) > rank(state_))) {
    write_al_status();
    return;
  }
  if (const std::uint16_t c = transition_check(state_, *requested); c != 0) {
    refuse(c);
    return;
  }
  if (state_ == AlState::SafeOp && *requested == AlState::Op && !rx_pdo_.empty() && !outputs_received_) {
    // Firmware waits for the first valid outputs before it enters OP.
    op_pending_ = true;
    op_pending_since_ = now_ns_;
    write_al_status();
    return;
  }
  change_state(*requested);
}

std::uint16_t EscCore::transition_check(AlState from, AlState to) {
  if (to == AlState::Init) {
    return 0;
  }
  const bool has_mailbox = mbx_out_sm_ >= 0 && mbx_in_sm_ >= 0;
  switch (from) {
    case AlState::Init:
      if (to == AlState::PreOp) {
        return has_mailbox ? check_mailbox(code(AlStatusCode::InvalidMailboxConfiguration)) : 0;
      }
      if (to == AlState::Bootstrap) {
        if (!has_mailbox || !device_->sii().bootstrap_mailbox.present()) {
          return code(AlStatusCode::BootstrapNotSupported);
        }
        return check_mailbox(code(AlStatusCode::InvalidBootstrapMailboxConfiguration));
      }
      return code(AlStatusCode::InvalidRequestedStateChange);
    case AlState::PreOp:
      if (to == AlState::SafeOp) {
        if (const std::uint16_t c = check_process_data(); c != 0) {
          return c;
        }
        return device_->check_transition(from, to);
      }
      return code(AlStatusCode::InvalidRequestedStateChange);
    case AlState::SafeOp:
      if (to == AlState::PreOp || to == AlState::Op) {
        return device_->check_transition(from, to);
      }
      return code(AlStatusCode::InvalidRequestedStateChange);
    case AlState::Op:
      return to == AlState::SafeOp || to == AlState::PreOp ? 0
                                                           : code(AlStatusCode::InvalidRequestedStateChange);
    case AlState::Bootstrap:
      return code(AlStatusCode::InvalidRequestedStateChange);  // BOOT only goes back to INIT
  }
  return code(AlStatusCode::InvalidRequestedStateChange);
}

std::uint16_t EscCore::check_mailbox(std::uint16_t error_code) const {
  // SM0 master→slave, SM1 slave→master: enabled, mailbox mode, right
  // direction, a sensible size inside process RAM and no overlap.
  const SyncManagerConfig out = sms_.config(mem_, static_cast<unsigned>(mbx_out_sm_));
  const SyncManagerConfig in = sms_.config(mem_, static_cast<unsigned>(mbx_in_sm_));
  auto valid = [this](const SyncManagerConfig& c, SyncManagerDirection dir) {
    return c.enabled() && c.mode_valid() && c.mode() == SyncManagerMode::mailbox && c.direction() == dir &&
           c.length >= kMinMailboxSize && c.length <= kMaxMailboxSize && c.start >= reg::kProcessRam &&
           std::uint32_t{c.start} + c.length <= ram_end_;
  };
  if (!valid(out, SyncManagerDirection::write) || !valid(in, SyncManagerDirection::read)) {
    return error_code;
  }
  const bool overlap = out.start < in.start + in.length && in.start < out.start + out.length;
  return overlap ? error_code : 0;
}

std::uint16_t EscCore::check_sm(int sm, std::size_t bytes, bool outputs) const {
  const std::uint16_t size_error = outputs ? code(AlStatusCode::InvalidOutputConfiguration)
                                           : code(AlStatusCode::InvalidInputConfiguration);
  if (bytes == 0) {
    return 0;
  }
  if (sm < 0) {
    return size_error;
  }
  const SyncManagerConfig c = sms_.config(mem_, static_cast<unsigned>(sm));
  if (!c.enabled()) {
    return size_error;
  }
  const auto direction = outputs ? SyncManagerDirection::write : SyncManagerDirection::read;
  if (!c.mode_valid() || c.mode() != SyncManagerMode::buffered || c.direction() != direction) {
    return code(AlStatusCode::InvalidSyncManagerConfiguration);
  }
  const std::uint32_t footprint = bytes > 1 ? 3U * c.length : c.length;  // 3 buffers
  if (c.length != bytes || std::uint32_t{c.start} + footprint > ram_end_) {
    return size_error;
  }
  return 0;
}

std::uint16_t EscCore::check_process_data() {
  if (const std::uint16_t c = rx_pdo_.build(device_->objects(), kRxPdoAssignment); c != 0) {
    return c;
  }
  if (const std::uint16_t c = tx_pdo_.build(device_->objects(), kTxPdoAssignment); c != 0) {
    return c;
  }
  if (const std::uint16_t c = check_sm(out_sm_, rx_pdo_.byte_size(), true); c != 0) {
    return c;
  }
  if (const std::uint16_t c = check_sm(in_sm_, tx_pdo_.byte_size(), false); c != 0) {
    return c;
  }
  return check_dc_sync();
}

std::uint16_t EscCore::check_dc_sync() const {
  // ETG.1020 §21: synchronization type 2 in 0x1C32:01 means "DC SYNC0"; then
  // the master must have started SYNC0 with a cycle time before SAFEOP.
  const OdEntry* sync_type = device_->objects().find(0x1C32, 1);
  if (sync_type == nullptr || sync_type->get<std::uint16_t>() != 2) {
    return 0;
  }
  const std::uint8_t wanted = reg::kDcActivationCyclic | reg::kDcActivationSync0;
  if ((mem_.get<std::uint8_t>(reg::kDcActivation) & wanted) != wanted) {
    return code(AlStatusCode::InvalidDcSyncConfiguration);
  }
  return mem_.get<std::uint32_t>(reg::kDcSync0CycleTime) == 0 ? code(AlStatusCode::DcInvalidSync0CycleTime)
                                                              : 0;
}

void EscCore::change_state(AlState to) {
  const AlState from = state_;
  if (from == AlState::Op) {
    device_->apply_safe_outputs();
  }
  state_ = to;
  if (rank(to) < rank(AlState::SafeOp)) {
    rx_pdo_.clear();
    tx_pdo_.clear();
  }
  if (to == AlState::Init) {
    mailbox_.reset();
  }
  if (to == AlState::SafeOp && from == AlState::PreOp) {
    outputs_received_ = false;
  }
  if (to == AlState::Op) {
    watchdog_last_ = now_ns_;
    watchdog_expired_ = false;
    mem_.put<std::uint16_t>(reg::kWatchdogStatusProcessData, 1);
  }
  if (!al_error_) {
    al_code_ = 0;
  }
  apply_pdi_sync_managers();
  write_al_status();
  device_->on_state_change(from, to);
  if (to == AlState::SafeOp || to == AlState::Op) {
    publish_inputs();  // valid inputs from the first frame on
  }
}

void EscCore::refuse(std::uint16_t c) {
  al_error_ = true;
  al_code_ = c;
  write_al_status();
}

void EscCore::write_al_status() {
  AlStatus status = AlStatus::of(state_, al_error_);
  status.id_loaded = id_requested_;
  const std::uint16_t value = status.encode();
  if (value != mem_.get<std::uint16_t>(reg::kAlStatus)) {
    al_event_ = true;
  }
  mem_.put<std::uint16_t>(reg::kAlStatus, value);
  // With the identification requested, 0x0134 shows the device ID instead.
  mem_.put<std::uint16_t>(reg::kAlStatusCode, id_requested_ ? options_.device_id : al_code_);
}

void EscCore::apply_pdi_sync_managers() {
  // The firmware opens the mailbox SyncManagers from PREOP (and BOOT) on and
  // the process-data ones from SAFEOP on; until then the master's accesses
  // to their areas are denied.
  const bool mailbox = state_ != AlState::Init;
  const bool process_data = rank(state_) >= rank(AlState::SafeOp);
  const auto& sms = device_->sii().sync_managers;
  for (unsigned n = 0; n < sms_.count() && n < sms.size(); ++n) {
    switch (sms[n].type) {
      case SiiSyncManagerType::mailbox_out:
      case SiiSyncManagerType::mailbox_in:
        sms_.set_pdi_enabled(mem_, n, mailbox);
        break;
      case SiiSyncManagerType::outputs:
      case SiiSyncManagerType::inputs:
        sms_.set_pdi_enabled(mem_, n, process_data);
        break;
      case SiiSyncManagerType::unused:
        break;
    }
  }
}

std::int64_t EscCore::watchdog_time_ns() const {
  // Watchdog unit = (divider + 2) · 40 ns (section II §3.27).
  const std::int64_t divider = mem_.get<std::uint16_t>(reg::kWatchdogDivider);
  const std::int64_t time = mem_.get<std::uint16_t>(reg::kWatchdogTimeProcessData);
  return (divider + 2) * 40 * time;
}

void EscCore::trigger_watchdog(std::int64_t now) {
  watchdog_last_ = now;
  if (watchdog_expired_) {
    watchdog_expired_ = false;
  }
  mem_.put<std::uint16_t>(reg::kWatchdogStatusProcessData, 1);
}

void EscCore::check_watchdog(std::int64_t now) {
  if (state_ != AlState::Op || watchdog_expired_ || out_sm_ < 0 ||
      !sms_.active(static_cast<unsigned>(out_sm_)) ||
      !sms_.watchdog_trigger(static_cast<unsigned>(out_sm_))) {
    return;
  }
  const std::int64_t limit = watchdog_time_ns();
  if (limit == 0 || now - watchdog_last_ < limit) {
    return;
  }
  // Expired: outputs to their safe state, OP → SAFEOP + ERROR, code 0x001B.
  watchdog_expired_ = true;
  ++watchdog_expirations_;
  mem_.put<std::uint16_t>(reg::kWatchdogStatusProcessData, 0);
  mem_.put<std::uint8_t>(
      reg::kWatchdogCounterProcessData,
      static_cast<std::uint8_t>(mem_.get<std::uint8_t>(reg::kWatchdogCounterProcessData) + 1U));
  mem_.put<std::uint32_t>(reg::kDigitalOutputData, 0);
  al_error_ = true;
  al_code_ = code(AlStatusCode::SyncManagerWatchdog);
  change_state(AlState::SafeOp);
}

}  // namespace sf::ethercat::slave::detail
