// Mailbox transport over the mailbox SyncManagers (ETG.1000.4 §5.6, ET1100
// datasheet II §12 "SyncManager", mailbox mode): SM0 carries master → slave
// messages, SM1 slave → master. A write fills the whole SM0 buffer (the ESC
// marks the mailbox full when its last byte is written); a read polls SM1
// status bit 3 "mailbox full", then reads the whole SM1 buffer. A read whose
// frame got lost has emptied the mailbox on the slave: the repeat request
// (SM1 activate bit 1, acknowledged in PDI control bit 1) makes the slave put
// the last message in again.
#include <algorithm>
#include <array>
#include <optional>

#include <fmt/format.h>

#include "poll.hpp"
#include "sf/ethercat/mailbox.hpp"
#include "sf/ethercat/master/master.hpp"

namespace sf::ethercat::master {
namespace {

// Repeat requests per message, and messages skipped as repeats of the last.
constexpr int kMaxRepeats = 8;
constexpr int kMaxSkipped = 8;

std::uint16_t sm_register(unsigned sm, std::uint16_t offset) {
  return static_cast<std::uint16_t>(reg::sync_manager(sm) + offset);
}

// SM0/SM1 as the SII describes them, falling back to the standard mailbox
// words when the SyncM category is missing.
SyncManagerConfig mailbox_sm(const SlaveInfo& s, unsigned sm) {
  const bool out = sm == 0;
  const auto wanted = out ? SiiSyncManagerType::mailbox_out : SiiSyncManagerType::mailbox_in;
  const auto start = out ? s.mailbox.rx_offset : s.mailbox.tx_offset;
  const auto length = out ? s.mailbox.rx_size : s.mailbox.tx_size;
  auto config = SyncManagerConfig::make(start, length, SyncManagerMode::mailbox,
                                        out ? SyncManagerDirection::write : SyncManagerDirection::read);
  if (sm < s.sii.sync_managers.size() && s.sii.sync_managers[sm].type == wanted) {
    config.control = s.sii.sync_managers[sm].control;
  }
  return config;
}

// For polls: a frame that got lost answers "not yet" instead of failing;
// the poll's own deadline bounds the waiting.
template <typename T, typename Done>
Result<bool> not_yet_if_lost(const Result<T>& r, Done&& done) {
  if (!r) {
    if (r.error().code == Errc::timeout) {
      return false;
    }
    return r.error();
  }
  return done(*r);
}

}  // namespace

Status Master::configure_mailbox(std::size_t position) {
  if (position >= slaves_.size()) {
    return make_error(Errc::invalid_argument, fmt::format("no slave at position {}", position));
  }
  auto& s = slaves_[position];
  if (!s.mailbox.present()) {
    return {};
  }
  std::array<std::uint8_t, 2 * SyncManagerConfig::kSize> both{};
  const auto sm0 = mailbox_sm(s, 0).encode();
  const auto sm1 = mailbox_sm(s, 1).encode();
  std::copy(sm0.begin(), sm0.end(), both.begin());
  std::copy(sm1.begin(), sm1.end(), both.begin() + SyncManagerConfig::kSize);
  SF_TRY(bus_.write_one(Command::FPWR, s.station, reg::sync_manager(0), both));
  s.mailbox.counter = 0;
  s.mailbox.last_received_counter = 0;
  return {};
}

std::uint8_t Master::next_mailbox_counter(std::size_t position) {
  if (position >= slaves_.size()) {
    return 0;
  }
  auto& m = slaves_[position].mailbox;
  m.counter = ethercat::next_mailbox_counter(m.counter);
  return m.counter;
}

Status Master::mailbox_write(std::size_t position, ByteSpan message) {
  if (position >= slaves_.size()) {
    return make_error(Errc::invalid_argument, fmt::format("no slave at position {}", position));
  }
  std::lock_guard lock(control_mutex_);
  const auto& s = slaves_[position];
  if (!s.mailbox.present()) {
    return make_error(Errc::unsupported, fmt::format("slave {} has no mailbox", position));
  }
  if (message.size() > s.mailbox.rx_size) {
    return make_error(Errc::invalid_argument,
                      fmt::format("mailbox message of {} bytes exceeds slave {}'s {} bytes", message.size(),
                                  position, s.mailbox.rx_size));
  }
  std::array<Datagram, 1> write{Datagram{Command::FPWR, 0, Datagram::physical(s.station, s.mailbox.rx_offset),
                                         0, false, Bytes(message.begin(), message.end()), 0}};
  write[0].data.resize(s.mailbox.rx_size, 0);
  bool unsure = false;  // the last write's frame was lost: did it arrive?
  auto written = [&]() -> Result<bool> {
    if (unsure) {
      // If the message waits in SM0 or is already answered in SM1, it
      // arrived; if that cannot be read now either, ask again next time.
      auto arrived = delivered(position);
      if (!arrived) {
        return not_yet_if_lost(arrived, [](bool yes) { return yes; });
      }
      if (*arrived) {
        return true;
      }
      unsure = false;
    }
    // Sent once: a resent copy of a message the slave already took would be
    // executed twice by slaves that do not check the mailbox counter.
    auto st = bus_.transceive(write, 0);
    if (st) {
      return write[0].wkc == 1;  // WKC 0: SM0 still full, try again
    }
    if (st.error().code != Errc::timeout) {
      return st.error();
    }
    unsure = true;
    return false;
  };
  return detail::poll_until(clock_, options_.mailbox_timeout, options_.poll_interval,
                            fmt::format("slave {} mailbox write (SM0 full)", position), written);
}

Result<bool> Master::delivered(std::size_t position) {
  const auto& s = slaves_[position];
  std::array<std::uint8_t, reg::kSyncManagerSize * 2> sms{};
  SF_TRY(bus_.read_one(Command::FPRD, s.station, reg::sync_manager(0), sms));
  if ((sms[reg::kSmStatus] & sm::kStatusMailboxFull) != 0) {
    return true;  // still waiting in SM0
  }
  if ((sms[reg::kSyncManagerSize + reg::kSmStatus] & sm::kStatusMailboxFull) == 0) {
    return false;
  }
  // An answer waits in SM1. Only its header is read — the ESC releases a
  // mailbox when its last byte is read — to tell a new answer from a
  // repeat of the one we already have.
  std::array<std::uint8_t, kMailboxHeaderSize> header{};
  SF_TRY(bus_.read_one(Command::FPRD, s.station, s.mailbox.tx_offset, header));
  auto decoded = MailboxHeader::decode(header);
  if (!decoded) {
    return true;  // something new, if unreadable: let the reader deal with it
  }
  return decoded->counter == 0 || decoded->counter != s.mailbox.last_received_counter;
}

Result<Bytes> Master::mailbox_read(std::size_t position, std::chrono::nanoseconds timeout) {
  if (position >= slaves_.size()) {
    return make_error(Errc::invalid_argument, fmt::format("no slave at position {}", position));
  }
  std::lock_guard lock(control_mutex_);
  auto& s = slaves_[position];
  if (!s.mailbox.present() || s.mailbox.tx_size < kMailboxHeaderSize) {
    return make_error(Errc::unsupported, fmt::format("slave {} has no mailbox", position));
  }
  Bytes buffer(s.mailbox.tx_size, 0);
  auto full = [&]() -> Result<bool> {
    return not_yet_if_lost(bus_.fprd<std::uint8_t>(s.station, sm_register(1, reg::kSmStatus)),
                           [](std::uint8_t status) { return (status & sm::kStatusMailboxFull) != 0; });
  };
  int repeats = 0;
  int skipped = 0;
  while (repeats <= kMaxRepeats && skipped <= kMaxSkipped) {
    SF_TRY(detail::poll_until(clock_, timeout, options_.poll_interval,
                              fmt::format("slave {} mailbox read (SM1 empty)", position), full));
    auto wkc = bus_.read(Command::FPRD, Datagram::physical(s.station, s.mailbox.tx_offset), buffer);
    if (wkc && *wkc == 1) {
      // A message with the counter of the previous one is a repeat of what
      // we already have (ETG.1000.4 §5.6); wait for the next.
      auto header = MailboxHeader::decode(buffer);
      const std::uint8_t counter = header ? header->counter : 0;
      if (counter != 0 && counter == s.mailbox.last_received_counter) {
        log_->warn("slave {}: repeated mailbox message (counter {}) dropped", position, counter);
        ++skipped;
        continue;
      }
      s.mailbox.last_received_counter = counter;
      return buffer;
    }
    // The read emptied the mailbox but its frame did not come back.
    log_->warn("slave {}: mailbox read lost, repeat request", position);
    ++mailbox_repeats_;
    ++repeats;
    SF_TRY(repeat_request(position, timeout));
  }
  return make_error(Errc::timeout,
                    fmt::format("slave {}: mailbox read failed after {} repeats", position, kMaxRepeats));
}

Status Master::repeat_request(std::size_t position, std::chrono::nanoseconds timeout) {
  // ETG.1000.4 §5.6, datasheet II 0x0806 bit 1: toggle the repeat request of
  // SM1; the slave writes the last message again and toggles its acknowledge
  // (0x0807 bit 1) to match.
  const auto station = slaves_[position].station;
  std::optional<std::uint8_t> target;  // SM1 activate with the repeat bit toggled once
  auto toggled = [&]() -> Result<bool> {
    if (!target) {
      auto activate = bus_.fprd<std::uint8_t>(station, sm_register(1, reg::kSmActivate));
      if (!activate) {
        return not_yet_if_lost(Result<bool>{activate.error()}, [](bool b) { return b; });
      }
      target = static_cast<std::uint8_t>(*activate ^ sm::kActivateRepeat);
    }
    // Writing the same value again is harmless; toggling twice would ask
    // for two repeats.
    auto st = bus_.fpwr<std::uint8_t>(station, sm_register(1, reg::kSmActivate), *target);
    return st ? Result<bool>{true} : not_yet_if_lost(Result<bool>{st.error()}, [](bool b) { return b; });
  };
  SF_TRY(detail::poll_until(clock_, timeout, options_.poll_interval,
                            fmt::format("slave {} mailbox repeat request", position), toggled));
  const bool want = (*target & sm::kActivateRepeat) != 0;
  auto acknowledged = [&]() -> Result<bool> {
    return not_yet_if_lost(bus_.fprd<std::uint8_t>(station, sm_register(1, reg::kSmPdiControl)),
                           [&](std::uint8_t pdi) { return ((pdi & sm::kPdiRepeatAck) != 0) == want; });
  };
  return detail::poll_until(clock_, timeout, options_.poll_interval,
                            fmt::format("slave {} mailbox repeat acknowledge", position), acknowledged);
}

}  // namespace sf::ethercat::master
