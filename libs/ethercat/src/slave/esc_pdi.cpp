// The firmware side of the ESC (what a slave's microcontroller does through
// the PDI): publish inputs, take outputs, serve the mailbox, run timers.
#include "esc_core.hpp"
#include "sf/ethercat/al_status_codes.hpp"

namespace sf::ethercat::slave::detail {

void EscCore::timers(std::int64_t now) {
  sii_.poll(mem_, now);
  check_watchdog(now);
  if (op_pending_ && now - op_pending_since_ >= options_.op_outputs_timeout.count()) {
    op_pending_ = false;
    refuse(static_cast<std::uint16_t>(AlStatusCode::SyncManagerWatchdog));
  }
  std::uint64_t last = 0;
  if (const std::uint32_t events = dc_.poll_sync0(mem_, now, &last); events != 0) {
    device_->on_sync0(last, events);
  }
  device_->tick(Clock::time_point(std::chrono::nanoseconds(now)));
  if (mbx_in_sm_ >= 0) {
    fill_read_mailbox();  // the device may have raised an emergency
  }
}

void EscCore::publish_inputs() {
  if ((state_ != AlState::SafeOp && state_ != AlState::Op) || in_sm_ < 0 || tx_pdo_.empty()) {
    return;
  }
  const auto sm = static_cast<unsigned>(in_sm_);
  if (!sms_.active(sm) || !sms_.pdi_enabled(sm)) {
    return;
  }
  device_->update_inputs();
  const MutableByteSpan inputs = sms_.pdi_inputs(mem_, sm);
  tx_pdo_.pack(inputs);
  published_inputs_.assign(inputs.begin(), inputs.end());
  sms_.pdi_commit_inputs(mem_, sm);
}

void EscCore::exchange_outputs(std::uint16_t written) {
  if (out_sm_ < 0 || (written & (1U << static_cast<unsigned>(out_sm_))) == 0) {
    return;
  }
  const auto sm = static_cast<unsigned>(out_sm_);
  if (sms_.watchdog_trigger(sm)) {
    trigger_watchdog(now_ns_);
  }
  if (state_ != AlState::SafeOp && state_ != AlState::Op) {
    return;
  }
  bool fresh = false;
  const ByteSpan outputs = sms_.pdi_outputs(mem_, sm, &fresh);
  last_outputs_.assign(outputs.begin(), outputs.end());
  outputs_received_ = true;
  if (op_pending_) {
    op_pending_ = false;
    change_state(AlState::Op);
  }
  if (state_ == AlState::Op) {  // in SAFEOP outputs are received but not applied
    rx_pdo_.unpack(outputs);
    device_->on_outputs();
  }
}

void EscCore::service_mailbox(std::uint16_t written, std::uint16_t read) {
  if (mbx_out_sm_ < 0 || mbx_in_sm_ < 0) {
    return;
  }
  const auto out = static_cast<unsigned>(mbx_out_sm_);
  const auto in = static_cast<unsigned>(mbx_in_sm_);
  if ((read & (1U << in)) != 0) {
    mailbox_.read_done();
  }
  if (repeat_pending_) {
    repeat_pending_ = false;
    repeat_mailbox();
  }
  if ((written & (1U << out)) != 0) {
    const ByteSpan request = sms_.pdi_take_mailbox(mem_, out);
    if (!request.empty()) {
      mailbox_.on_request(request, state_, sms_.config(mem_, in).length);
    }
  }
  fill_read_mailbox();
}

void EscCore::fill_read_mailbox() {
  const auto in = static_cast<unsigned>(mbx_in_sm_);
  if (!sms_.active(in) || !sms_.pdi_enabled(in)) {
    return;
  }
  while (const Bytes* reply = mailbox_.next_reply()) {
    if (sms_.mailbox_full(in)) {
      return;
    }
    if (sms_.pdi_put_mailbox(mem_, in, *reply)) {
      mailbox_.put_done();
      return;
    }
    // Larger than the mailbox the master configured: it can never be sent.
    mailbox_.drop_front();
  }
}

void EscCore::repeat_mailbox() {
  // Repeat request (ETG.1000.4 §5.6.1.2): the master toggled SM1 activate
  // bit 1; write the last reply again and toggle PDI control bit 1 to match.
  const auto in = static_cast<unsigned>(mbx_in_sm_);
  const std::uint32_t base = reg::sync_manager(in);
  if (const Bytes* last = mailbox_.repeat(); last != nullptr) {
    sms_.set_pdi_enabled(mem_, in, false);  // drops an unread reply (requeued by repeat())
    sms_.set_pdi_enabled(mem_, in, true);
    sms_.pdi_put_mailbox(mem_, in, *last);
  }
  const bool request = (mem_.get<std::uint8_t>(base + reg::kSmActivate) & sm::kActivateRepeat) != 0;
  mem_.set_bits(base + reg::kSmPdiControl, sm::kPdiRepeatAck, request);
}

}  // namespace sf::ethercat::slave::detail
