#include "sync_manager_unit.hpp"

#include <algorithm>
#include <cstring>

namespace sf::ethercat::slave::detail {

namespace {
constexpr std::uint8_t kNoBufferWritten = 0x30;  // status bits 5:4 = 11
}

void SyncManagerUnit::power_on(EscMemory& m, unsigned count) {
  count_ = std::min<unsigned>(count, reg::kMaxSyncManagers);
  for (unsigned n = 0; n < reg::kMaxSyncManagers; ++n) {
    sms_[n] = State{};
    if (n < count_) {
      std::fill(m.at(reg::sync_manager(n)), m.at(reg::sync_manager(n) + SyncManagerConfig::kSize),
                std::uint8_t{0});
    }
  }
  written_ = read_ = 0;
  rebuild_index();
}

SyncManagerConfig SyncManagerUnit::config(const EscMemory& m, unsigned n) const {
  auto decoded = SyncManagerConfig::decode(ByteSpan(m.at(reg::sync_manager(n)), SyncManagerConfig::kSize));
  return decoded ? *decoded : SyncManagerConfig{};
}

bool SyncManagerUnit::on_written(EscMemory& m, unsigned n) {
  State& s = sms_[n];
  const std::uint32_t base = reg::sync_manager(n);
  const std::uint8_t activate = *m.at(base + reg::kSmActivate);
  const bool enable = (activate & sm::kActivateEnable) != 0;
  const bool repeat_toggled = ((activate ^ s.last_activate) & sm::kActivateRepeat) != 0;
  s.last_activate = activate;
  const auto start = m.get<std::uint16_t>(base + reg::kSmStart);
  const auto length = m.get<std::uint16_t>(base + reg::kSmLength);
  const std::uint8_t control = *m.at(base + reg::kSmControl);
  if (enable != s.ecat_enabled || start != s.start || length != s.length || control != s.control) {
    s.start = start;
    s.length = length;
    s.control = control;
    s.mailbox = (control & sm::kModeMask) == static_cast<std::uint8_t>(SyncManagerMode::mailbox);
    s.ecat_writes = (control & sm::kDirectionMask) != 0;
    s.ecat_enabled = enable;
    reset_runtime(m, n);
    rebuild_index();
  }
  return repeat_toggled && s.ecat_enabled;
}

void SyncManagerUnit::set_pdi_enabled(EscMemory& m, unsigned n, bool enabled) {
  State& s = sms_[n];
  if (s.pdi_enabled == enabled) {
    return;
  }
  s.pdi_enabled = enabled;
  m.set_bits(reg::sync_manager(n) + reg::kSmPdiControl, sm::kPdiDeactivate, !enabled);
  reset_runtime(m, n);
}

void SyncManagerUnit::reset_runtime(EscMemory& m, unsigned n) {
  State& s = sms_[n];
  s.full = false;
  s.ecat = 0;
  s.pdi = 1;
  s.next = kNone;
  written_ = static_cast<std::uint16_t>(written_ & ~(1U << n));
  read_ = static_cast<std::uint16_t>(read_ & ~(1U << n));
  update_status(m, n);
}

void SyncManagerUnit::update_status(EscMemory& m, unsigned n) {
  const State& s = sms_[n];
  std::uint8_t status = 0;
  if (s.mailbox) {
    if (s.full) {
      status |= sm::kStatusMailboxFull;
      status |= s.ecat_writes ? sm::kStatusWriteEvent : sm::kStatusReadEvent;
    }
  } else if (s.next != kNone) {
    status = static_cast<std::uint8_t>(s.next << 4U);
    status |= s.ecat_writes ? sm::kStatusWriteEvent : sm::kStatusReadEvent;
  } else {
    status = kNoBufferWritten;
  }
  *m.at(reg::sync_manager(n) + reg::kSmStatus) = status;
}

void SyncManagerUnit::rebuild_index() {
  active_count_ = 0;
  for (unsigned n = 0; n < count_; ++n) {
    if (active(n)) {
      order_[active_count_++] = static_cast<std::uint8_t>(n);
    }
  }
  std::sort(order_.begin(), order_.begin() + active_count_,
            [this](std::uint8_t a, std::uint8_t b) { return sms_[a].start < sms_[b].start; });
}

SyncManagerUnit::Hit SyncManagerUnit::lookup(std::uint32_t address, std::uint32_t end) const {
  for (unsigned i = 0; i < active_count_; ++i) {
    const State& s = sms_[order_[i]];
    if (address < s.start) {
      return Hit{-1, std::min<std::uint32_t>(end, s.start)};
    }
    if (address < s.end()) {
      return Hit{order_[i], std::min(end, s.end())};
    }
  }
  return Hit{-1, end};
}

std::uint32_t SyncManagerUnit::ecat_address(unsigned n, std::uint32_t address) const {
  const State& s = sms_[n];
  return s.buffered() ? address + std::uint32_t{s.ecat} * s.length : address;
}

bool SyncManagerUnit::ecat_read(EscMemory& m, unsigned n, std::uint32_t address, std::uint8_t* dst,
                                std::size_t len) {
  State& s = sms_[n];
  if (s.length == 1) {  // unbuffered, but the access still counts as a read event
    std::memcpy(dst, m.at(address), len);
    read_ = static_cast<std::uint16_t>(read_ | (1U << n));
    return true;
  }
  if (!s.pdi_enabled || s.ecat_writes) {
    return false;  // deactivated by the PDI, or the master reading its own write area
  }
  const bool last = address + len == s.end();
  if (s.mailbox) {
    if (!s.full) {
      return false;
    }
    std::memcpy(dst, m.at(address), len);
    if (last) {
      s.full = false;
      read_ = static_cast<std::uint16_t>(read_ | (1U << n));
      update_status(m, n);
    }
    return true;
  }
  // 3-buffer: reading the first byte opens the newest complete buffer.
  if (address == s.start && s.next != kNone) {
    s.ecat = s.next;
    s.next = kNone;
  }
  const std::uint32_t from = ecat_address(n, address);
  if (from + len <= EscMemory::kSize) {
    std::memcpy(dst, m.at(from), len);
  }
  if (last) {
    read_ = static_cast<std::uint16_t>(read_ | (1U << n));
    update_status(m, n);
  }
  return true;
}

bool SyncManagerUnit::ecat_write(EscMemory& m, unsigned n, std::uint32_t address, const std::uint8_t* src,
                                 std::size_t len) {
  State& s = sms_[n];
  if (s.length == 1) {
    std::memcpy(m.at(address), src, len);
    written_ = static_cast<std::uint16_t>(written_ | (1U << n));
    return true;
  }
  if (!s.pdi_enabled || !s.ecat_writes) {
    return false;
  }
  const bool last = address + len == s.end();
  if (s.mailbox) {
    if (s.full) {
      return false;
    }
    std::memcpy(m.at(address), src, len);
    if (last) {
      s.full = true;
      written_ = static_cast<std::uint16_t>(written_ | (1U << n));
      update_status(m, n);
    }
    return true;
  }
  const std::uint32_t to = ecat_address(n, address);
  if (to + len <= EscMemory::kSize) {
    std::memcpy(m.at(to), src, len);
  }
  if (last) {
    // The completed buffer becomes the newest; the master continues in the
    // buffer that is neither the PDI's nor the newest.
    const std::uint8_t done = s.ecat;
    s.ecat = s.next != kNone ? s.next : free_buffer(done, s.pdi);
    s.next = done;
    written_ = static_cast<std::uint16_t>(written_ | (1U << n));
    update_status(m, n);
  }
  return true;
}

ByteSpan SyncManagerUnit::pdi_take_mailbox(EscMemory& m, unsigned n) {
  State& s = sms_[n];
  if (!s.mailbox || !s.ecat_writes || !s.full || s.end() > EscMemory::kSize) {
    return {};
  }
  s.full = false;
  update_status(m, n);
  return ByteSpan(m.at(s.start), s.length);
}

bool SyncManagerUnit::pdi_put_mailbox(EscMemory& m, unsigned n, ByteSpan message) {
  State& s = sms_[n];
  if (!s.mailbox || s.ecat_writes || s.full || !active(n) || message.size() > s.length ||
      s.end() > EscMemory::kSize) {
    return false;
  }
  std::memcpy(m.at(s.start), message.data(), message.size());
  std::fill(m.at(s.start + static_cast<std::uint32_t>(message.size())), m.at(s.end()), std::uint8_t{0});
  s.full = true;
  update_status(m, n);
  return true;
}

ByteSpan SyncManagerUnit::pdi_outputs(EscMemory& m, unsigned n, bool* fresh) {
  State& s = sms_[n];
  if (fresh != nullptr) {
    *fresh = false;
  }
  if (s.length <= 1) {
    return s.end() <= EscMemory::kSize ? ByteSpan(m.at(s.start), s.length) : ByteSpan{};
  }
  if (s.next != kNone) {
    s.pdi = s.next;
    s.next = kNone;
    if (fresh != nullptr) {
      *fresh = true;
    }
    update_status(m, n);
  }
  const std::uint32_t at = std::uint32_t{s.start} + std::uint32_t{s.pdi} * s.length;
  return at + s.length <= EscMemory::kSize ? ByteSpan(m.at(at), s.length) : ByteSpan{};
}

MutableByteSpan SyncManagerUnit::pdi_inputs(EscMemory& m, unsigned n) {
  State& s = sms_[n];
  const std::uint32_t at = s.length <= 1 ? s.start : std::uint32_t{s.start} + std::uint32_t{s.pdi} * s.length;
  return at + s.length <= EscMemory::kSize ? MutableByteSpan(m.at(at), s.length) : MutableByteSpan{};
}

void SyncManagerUnit::pdi_commit_inputs(EscMemory& m, unsigned n) {
  State& s = sms_[n];
  if (s.length <= 1 || s.mailbox) {
    return;
  }
  const std::uint8_t done = s.pdi;
  s.pdi = s.next != kNone ? s.next : free_buffer(done, s.ecat);
  s.next = done;
  update_status(m, n);
}

}  // namespace sf::ethercat::slave::detail
