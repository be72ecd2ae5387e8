// Register side effects of one ESC: what happens when the master writes or
// reads a register that is more than memory (ET1100 datasheet section II).
#include <algorithm>

#include "esc_core.hpp"

namespace sf::ethercat::slave::detail {

namespace {

constexpr bool overlaps(std::uint32_t address, std::size_t n, std::uint32_t from, std::uint32_t to) {
  return address < to && address + n > from;
}

// ESC reset (section II §3.13): writing 'R', 'E', 'S' to 0x0040 in three
// consecutive frames resets the ESC; bits 1:0 read the progress.
constexpr std::uint8_t kResetSequence[] = {0x52, 0x45, 0x53};

// DL control loop setting of a port (0x0101, 2 bits per port).
enum class LoopControl : std::uint8_t { automatic = 0, auto_close = 1, open = 2, closed = 3 };

}  // namespace

bool EscCore::write_blocked(std::uint32_t address, RegGroup group) const {
  switch (group) {
    case RegGroup::sm_config:
      // r/(w): only while the SyncManager is disabled (section II Table 89).
      return sms_.active((address - reg::kSyncManagerBase) / 8U) ||
             (mem_.get<std::uint8_t>(reg::sync_manager((address - reg::kSyncManagerBase) / 8U) +
                                     reg::kSmActivate) &
              sm::kActivateEnable) != 0;
    case RegGroup::sii_control:
    case RegGroup::sii_registers:
      return sii_.busy();  // the EEPROM interface ignores writes while busy
    default:
      return false;
  }
}

void EscCore::before_read(std::uint32_t address, std::size_t n) {
  if (overlaps(address, n, reg::kSiiControlStatus, reg::kSiiData + 8U)) {
    sii_.before_read(mem_, now_ns_, overlaps(address, n, reg::kSiiControlStatus, reg::kSiiAddress));
  }
  if (overlaps(address, n, reg::kDcSystemTime, reg::kDcSystemTime + 8U)) {
    dc_.refresh_system_time(mem_, pass_.port0);
  }
  if (overlaps(address, n, reg::kEcatEventRequest, reg::kEcatEventRequest + 2U)) {
    update_event_request();
  }
}

void EscCore::after_read(std::uint32_t address, std::size_t n) {
  if (al_event_ && overlaps(address, n, reg::kAlStatus, reg::kAlStatus + 2U)) {
    al_event_ = false;  // reading AL status acknowledges the AL status event
  }
}

void EscCore::dispatch_writes() {
  if (touched_ == 0) {
    return;
  }
  const std::uint32_t touched = std::exchange(touched_, 0U);
  auto has = [touched](RegGroup g) { return (touched & (1U << static_cast<unsigned>(g))) != 0; };
  if (has(RegGroup::esc_reset)) {
    on_esc_reset(last_written_[reg::kEscResetEcat]);
  }
  if (has(RegGroup::dl_control)) {
    update_dl_status();
  }
  if (has(RegGroup::al_control)) {
    al_control_pending_ = true;
  }
  if (has(RegGroup::error_counters)) {
    std::fill(mem_.at(reg::kRxErrorCounter), mem_.at(reg::kLostLinkCounter + 4U), std::uint8_t{0});
  }
  if (has(RegGroup::watchdog_counters)) {
    mem_.put<std::uint16_t>(reg::kWatchdogCounterProcessData, 0);
  }
  if (has(RegGroup::sii_control)) {
    sii_.on_control_written(mem_, mem_.get<std::uint16_t>(reg::kSiiControlStatus), now_ns_);
  }
  for (unsigned n = 0; touched_fmmu_ != 0;
       ++n, touched_fmmu_ = static_cast<std::uint16_t>(touched_fmmu_ >> 1U)) {
    if ((touched_fmmu_ & 1U) != 0) {
      fmmus_.on_written(mem_, n);
    }
  }
  for (unsigned n = 0; touched_sm_ != 0; ++n, touched_sm_ = static_cast<std::uint16_t>(touched_sm_ >> 1U)) {
    if ((touched_sm_ & 1U) != 0 && sms_.on_written(mem_, n) && static_cast<int>(n) == mbx_in_sm_) {
      repeat_pending_ = true;
    }
  }
  if (has(RegGroup::dc_receive_time)) {
    dc_.latch_receive_times(mem_, DcPorts{pass_.port0, pass_.port1, pass_.port1_valid && forwards(1)});
  }
  if (has(RegGroup::dc_system_time)) {
    dc_.on_system_time_written(mem_, load_le<std::uint32_t>(&last_written_[reg::kDcSystemTime]), pass_.port0);
  }
  if (has(RegGroup::dc_speed_counter_start)) {
    dc_.on_speed_counter_start_written(mem_);
  }
  if (has(RegGroup::dc_cyclic)) {
    dc_.on_cyclic_written(mem_, pass_.port0);
  }
}

void EscCore::on_esc_reset(std::uint8_t value) {
  if (reset_sequence_ < 3 && value == kResetSequence[reset_sequence_]) {
    ++reset_sequence_;
  } else {
    reset_sequence_ = value == kResetSequence[0] ? 1 : 0;
  }
  mem_.put<std::uint8_t>(reg::kEscResetEcat, static_cast<std::uint8_t>(reset_sequence_ & 0x03U));
  if (reset_sequence_ == 3) {
    reset_pending_ = true;  // at the end of this frame
  }
}

bool EscCore::loop_closed(unsigned port) const {
  const auto control =
      static_cast<LoopControl>((unsigned{mem_.get<std::uint8_t>(reg::kDlControl + 1U)} >> (2U * port)) & 3U);
  switch (control) {
    case LoopControl::open:
      return false;
    case LoopControl::closed:
      return true;
    case LoopControl::automatic:
    case LoopControl::auto_close:
      break;
  }
  return !link_[port];
}

void EscCore::update_dl_status() {
  DlStatus dl;
  // PDI operational once the EEPROM's configuration area was loaded; the
  // emulated PDI never lets its watchdog expire.
  const bool loaded = (mem_.get<std::uint16_t>(reg::kSiiControlStatus) & reg::sii_control::kLoadError) == 0;
  dl.set(DlStatus::kPdiOperational, loaded);
  dl.set(DlStatus::kPdiWatchdogReloaded, true);
  dl.set(DlStatus::kEnhancedLinkDetection, true);
  for (unsigned p = 0; p < 4; ++p) {
    const bool implemented = port_kind(options_.port_descriptor, p) != PortKind::not_implemented;
    const bool link = implemented && link_[p];
    dl.set_link(p, link);
    dl.set_loop_closed(p, !implemented || loop_closed(p));
    dl.set_communication(p, link);
  }
  mem_.put<std::uint16_t>(reg::kDlStatus, dl.value);
}

void EscCore::update_event_request() {
  // ECAT event request (section II §3.23): bit 3 AL status event, bits 4..11
  // SyncManager n status when its ECAT interrupt (control bit 4) is enabled.
  std::uint16_t events = al_event_ ? 0x0008 : 0x0000;
  for (unsigned n = 0; n < std::min(sms_.count(), 8U); ++n) {
    const std::uint32_t base = reg::sync_manager(n);
    const bool enabled = (mem_.get<std::uint8_t>(base + reg::kSmControl) & sm::kEcatInterrupt) != 0;
    const std::uint8_t status = mem_.get<std::uint8_t>(base + reg::kSmStatus);
    if (enabled && sms_.active(n) && (status & (sm::kStatusWriteEvent | sm::kStatusReadEvent)) != 0) {
      events = static_cast<std::uint16_t>(events | (1U << (4U + n)));
    }
  }
  mem_.put<std::uint16_t>(reg::kEcatEventRequest, events);
}

}  // namespace sf::ethercat::slave::detail
