// SyncManagers (ET1100 datasheet section I §8, registers II §3.48 at
// 0x0800 + 8·n): they guard areas of ESC memory so that master and PDI never
// see half-written data.
//   mailbox mode (one buffer): the writer fills the buffer, writing the last
//     byte sets "mailbox full"; the reader may then read it, reading the last
//     byte empties it. Accesses to a full (write) or empty (read) mailbox are
//     denied: no data, no working counter.
//   buffered mode (3 buffers at start, start+len, start+2·len): the writer
//     always has a free buffer, completing it (last byte) makes it the
//     newest; the reader always gets the newest complete buffer.
// A SyncManager of length 1 buffers nothing: it only triggers the watchdog.
#pragma once

#include <array>
#include <cstdint>
#include <utility>

#include "esc_memory.hpp"
#include "sf/core/bytes.hpp"
#include "sf/ethercat/registers.hpp"

namespace sf::ethercat::slave::detail {

class SyncManagerUnit {
 public:
  static constexpr std::uint8_t kNone = 0xFF;

  struct Hit {
    int sm = -1;            // SyncManager covering the address, or -1
    std::uint32_t end = 0;  // where this piece ends (SM end or next SM start)
  };

  void power_on(EscMemory& m, unsigned count);
  // The master wrote configuration or activate registers of SM n.
  // Returns true if the repeat request bit (activate bit 1) toggled.
  bool on_written(EscMemory& m, unsigned n);
  // PDI side: deactivate (PDI control bit 0) as the firmware does per state.
  void set_pdi_enabled(EscMemory& m, unsigned n, bool enabled);
  // Which SM covers `address` and how far the piece goes (at most `end`).
  [[nodiscard]] Hit lookup(std::uint32_t address, std::uint32_t end) const;

  // ECAT accesses inside SM n's area; false = denied.
  bool ecat_read(EscMemory& m, unsigned n, std::uint32_t address, std::uint8_t* dst, std::size_t len);
  bool ecat_write(EscMemory& m, unsigned n, std::uint32_t address, const std::uint8_t* src, std::size_t len);
  // The memory an ECAT access to `address` would use (3-buffer redirection),
  // without side effects.
  [[nodiscard]] std::uint32_t ecat_address(unsigned n, std::uint32_t address) const;

  // Events since the last take: SMs whose buffer the master completed
  // writing / completed reading.
  std::uint16_t take_written() { return std::exchange(written_, std::uint16_t{0}); }
  std::uint16_t take_read() { return std::exchange(read_, std::uint16_t{0}); }

  // PDI side. Mailbox: the message the master wrote (empties the mailbox),
  // or an empty span if none; put a reply if the mailbox is empty.
  ByteSpan pdi_take_mailbox(EscMemory& m, unsigned n);
  bool pdi_put_mailbox(EscMemory& m, unsigned n, ByteSpan message);
  // Buffered: the newest outputs buffer; `fresh` says whether it is new.
  ByteSpan pdi_outputs(EscMemory& m, unsigned n, bool* fresh = nullptr);
  // Buffered: the buffer the PDI writes inputs into, then commit it.
  MutableByteSpan pdi_inputs(EscMemory& m, unsigned n);
  void pdi_commit_inputs(EscMemory& m, unsigned n);

  [[nodiscard]] bool active(unsigned n) const { return sms_[n].ecat_enabled && sms_[n].length > 0; }
  [[nodiscard]] bool pdi_enabled(unsigned n) const { return sms_[n].pdi_enabled; }
  [[nodiscard]] bool mailbox_full(unsigned n) const { return sms_[n].full; }
  [[nodiscard]] bool watchdog_trigger(unsigned n) const { return (sms_[n].control & sm::kWatchdog) != 0; }
  [[nodiscard]] SyncManagerConfig config(const EscMemory& m, unsigned n) const;
  [[nodiscard]] unsigned count() const { return count_; }

 private:
  struct State {
    std::uint16_t start = 0;
    std::uint16_t length = 0;
    std::uint8_t control = 0;
    bool ecat_enabled = false;
    bool pdi_enabled = true;
    bool mailbox = false;
    bool ecat_writes = false;  // direction: ECAT writes, PDI reads
    bool full = false;
    std::uint8_t ecat = 0;  // 3-buffer roles
    std::uint8_t pdi = 1;
    std::uint8_t next = kNone;
    std::uint8_t last_activate = 0;
    [[nodiscard]] bool buffered() const { return !mailbox && length > 1; }
    [[nodiscard]] std::uint32_t end() const { return std::uint32_t{start} + length; }
  };

  void reset_runtime(EscMemory& m, unsigned n);
  void update_status(EscMemory& m, unsigned n);
  void rebuild_index();
  static std::uint8_t free_buffer(std::uint8_t a, std::uint8_t b) {
    return static_cast<std::uint8_t>(3U - a - b);
  }

  std::array<State, reg::kMaxSyncManagers> sms_{};
  unsigned count_ = 0;
  // Active SMs sorted by start address, for lookup().
  std::array<std::uint8_t, reg::kMaxSyncManagers> order_{};
  unsigned active_count_ = 0;
  std::uint16_t written_ = 0;
  std::uint16_t read_ = 0;
};

}  // namespace sf::ethercat::slave::detail
