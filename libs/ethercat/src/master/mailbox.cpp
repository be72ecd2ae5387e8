// Mailbox transport over the mailbox SyncManagers (ETG.1000.4 §5.6, ET1100
// datasheet II §12 "SyncManager", mailbox mode): SM0 carries master → slave
// messages, SM1 slave → master. A write fills the whole SM0 buffer (the ESC
// marks the mailbox full when its last byte is written); a read polls SM1
// status bit 3 "mailbox full", then reads the whole SM1 buffer. Lost frames:
//   write  sent again with the same mailbox counter; a slave that got the
//          first one ignores the copy;
//   read   never read again (that would take the next queued message): the
//          repeat request (SM1 activate bit 1, acknowledged in PDI control
//          bit 1) makes the slave put the last message in again, and the
//          mailbox counter tells that copy from a message already received.
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
  auto written = [&]() -> Result<bool> {
    // A write whose frame got lost is sent again, unchanged: if the first one
    // arrived, the slave sees the same mailbox counter and ignores the copy
    // (ETG.1000.4 §5.6). Guessing from SM1 whether it arrived cannot work:
    // SM1 may hold an older message (an emergency) that looks like an answer.
    auto st = bus_.transceive(write, 0);
    if (st) {
      return write[0].wkc == 1;  // WKC 0: SM0 still full, try again
    }
    return not_yet_if_lost(Result<bool>{st.error()}, [](bool b) { return b; });
  };
  return detail::poll_until(clock_, options_.mailbox_timeout, options_.poll_interval,
                            fmt::format("slave {} mailbox write (SM0 full)", position), written);
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
    // One attempt only: a read whose answer got lost has emptied SM1, and a
    // second read would take the next queued message (an emergency, the next
    // fragment) while the lost one is gone for good. The repeat request
    // below brings the lost one back instead (ETG.1000.4 §5.6).
    std::array<Datagram, 1> read{Datagram{Command::FPRD, 0,
                                          Datagram::physical(s.station, s.mailbox.tx_offset), 0, false,
                                          Bytes(s.mailbox.tx_size, 0), 0}};
    auto st = bus_.transceive(read, 0);
    if (!st && st.error().code != Errc::timeout) {
      return st.error();
    }
    if (st && read[0].wkc == 1) {
      std::copy(read[0].data.begin(), read[0].data.end(), buffer.begin());
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
    // The read's frame did not come back (or found SM1 emptied by an earlier
    // one that did not come back): the message may be lost on the way.
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

Result<Bytes> Master::read_coe_answer(std::size_t position,
                                      const std::function<bool(const CoeMessage&)>& wanted) {
  // Whatever else the slave has queued (emergencies, answers the master gave
  // up on) is skipped until the answer comes or the mailbox timeout passes:
  // a drive with eight faulted axes queues eight emergencies at once.
  const auto deadline = clock_.now() + options_.mailbox_timeout;
  while (true) {
    const auto left = deadline - clock_.now();
    if (left <= std::chrono::nanoseconds{0}) {
      return make_error(
          Errc::timeout,
          fmt::format(
              "slave {}: no CoE answer within {} ms", position,
              std::chrono::duration_cast<std::chrono::milliseconds>(options_.mailbox_timeout).count()));
    }
    auto buffer = mailbox_read(position, left);
    if (!buffer) {
      return buffer.error();
    }
    auto mailbox = decode_mailbox(*buffer);
    if (!mailbox) {
      return mailbox.error().with_context(fmt::format("slave {} mailbox", position));
    }
    if (mailbox->header.type == MailboxType::Err) {
      auto err = decode_mailbox_error(mailbox->data);
      return make_error(Errc::remote, fmt::format("slave {}: mailbox error {}", position,
                                                  err ? describe(*err) : std::string_view{"(malformed)"}));
    }
    if (mailbox->header.type != MailboxType::CoE) {
      continue;
    }
    auto coe = decode_coe(*buffer);
    if (!coe) {
      return coe.error().with_context(fmt::format("slave {} CoE", position));
    }
    if (wanted(*coe)) {
      return buffer;
    }
    if (coe->coe.service == CoeService::Emergency) {
      if (auto e = CoeEmergency::decode(coe->body)) {
        log_->info("slave {}: emergency 0x{:04X} (error register 0x{:02X})", position, e->error_code,
                   e->error_register);
      }
    }
  }
}

}  // namespace sf::ethercat::master
