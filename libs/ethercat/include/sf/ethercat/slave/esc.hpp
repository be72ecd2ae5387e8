// Esc: one emulated EtherCAT slave controller, modelled on the ET1100
// (Beckhoff "EtherCAT Slave Controller" datasheet, section I technology and
// section II registers): a 64 KiB address space (registers 0x0000–0x0FFF,
// process RAM from 0x1000), datagram processing for all commands with the
// working-counter rules of wkc.hpp, FMMUs, SyncManagers, the SII EEPROM
// interface, the AL state machine, distributed clocks, the process-data
// watchdog and a CoE mailbox, with a Device behind the PDI.
//
// An Esc is driven by a Segment: begin_frame() when a frame reaches it,
// process() for each datagram in order (in place), end_frame() after the
// frame has passed (deferred PDI work: AL control, mailbox, outputs).
// Not thread-safe: one thread drives a segment.
#pragma once

#include <chrono>
#include <cstdint>
#include <memory>

#include "sf/core/bytes.hpp"
#include "sf/core/clock.hpp"
#include "sf/ethercat/frame.hpp"
#include "sf/ethercat/registers.hpp"

namespace sf::ethercat::slave {

class Device;
class ObjectDictionary;

struct EscOptions {
  // ESC information registers 0x0000–0x0008 (ET1100 values).
  std::uint8_t type = 0x11;
  std::uint8_t revision = 0x00;
  std::uint16_t build = 0x0003;
  std::uint8_t fmmus = 8;
  std::uint8_t sync_managers = 8;
  std::uint8_t ram_kib = 8;             // process RAM 0x1000 .. 0x1000 + 1024·ram_kib
  std::uint8_t port_descriptor = 0x0F;  // ports 0 and 1: MII, 2 and 3: not implemented
  std::uint16_t features = reg::feature::kDistributedClocks | reg::feature::kDc64Bit |
                           reg::feature::kEnhancedLinkDetectionMii | reg::feature::kSeparateFcsErrors |
                           reg::feature::kEnhancedDcSync;

  // SII EEPROM interface: 8 (ET1100) or 4 bytes per read (0x0502 bit 6), and
  // how long a command keeps the busy bit: until this much clock time has
  // passed or the status was polled this often, whichever comes first (a
  // master polling without letting time pass still makes progress).
  bool sii_read_8_bytes = true;
  std::chrono::nanoseconds sii_busy_time{std::chrono::microseconds{20}};
  unsigned sii_busy_polls = 1;

  // Local oscillator: drift against the segment clock and the value of the
  // local time when the segment clock reads 0.
  double drift_ppm = 0.0;
  std::int64_t local_time_offset_ns = 0;

  // SAFEOP→OP waits for the first valid outputs this long, then fails with
  // AL status code 0x001B (sync manager watchdog), as ETG firmware does.
  std::chrono::nanoseconds op_outputs_timeout{std::chrono::seconds{1}};
  // Explicit device identification (ETG.1000.6 §6.4.1, AL control bit 5).
  std::uint16_t device_id = 0;
};

// When a frame passes this ESC, in ns of the segment clock: the first bit at
// port 0 on the way out (where it is processed) and, if port 1 is open, the
// first bit at port 1 on the way back.
struct FramePass {
  std::int64_t port0 = 0;
  std::int64_t port1 = 0;
  bool port1_valid = false;
};

namespace detail {
class EscCore;
}

class Esc {
 public:
  Esc(std::unique_ptr<Device> device, const Clock& clock, EscOptions options = {});
  ~Esc();
  Esc(const Esc&) = delete;
  Esc& operator=(const Esc&) = delete;
  Esc(Esc&&) noexcept;
  Esc& operator=(Esc&&) noexcept;

  // --- driven by the segment ---
  void begin_frame(const FramePass& pass);
  // One datagram, in place: addresses it, reads/writes memory, adds to the
  // WKC, increments ADP for auto-increment and broadcast commands.
  void process(DatagramView datagram);
  void end_frame();
  // Timers (SII busy, watchdog, SYNC0, pending transitions) at clock.now().
  void poll();
  // The emulation itself did not run for `gap` (its process descheduled): frames the master
  // sent meanwhile wait in the link, so that time does not count against the master in the
  // process-data watchdog. Hardware never pauses; an emulator on a loaded host does.
  void emulation_paused(std::chrono::nanoseconds gap);
  // Power-on defaults: INIT, station address 0, SMs/FMMUs cleared, EEPROM reloaded.
  void power_on();
  // Physical link on a port (the segment's topology); DL status follows.
  void set_link(unsigned port, bool up);
  // A frame leaves through this port: link up and loop not forced closed (DL control).
  [[nodiscard]] bool forwards(unsigned port) const;

  // --- observation (what the PDI sees) ---
  [[nodiscard]] ByteSpan memory() const;
  [[nodiscard]] std::uint8_t read8(std::uint16_t address) const;
  [[nodiscard]] std::uint16_t read16(std::uint16_t address) const;
  [[nodiscard]] std::uint32_t read32(std::uint16_t address) const;
  [[nodiscard]] std::uint64_t read64(std::uint16_t address) const;
  [[nodiscard]] AlStatus al_status() const;
  [[nodiscard]] AlState state() const;
  [[nodiscard]] std::uint16_t al_status_code() const;
  [[nodiscard]] std::uint16_t station_address() const;
  [[nodiscard]] Bytes eeprom() const;
  [[nodiscard]] Device& device();
  [[nodiscard]] const Device& device() const;
  [[nodiscard]] ObjectDictionary& objects();

  // Distributed clocks: local time (ns) and DC system time at a segment-clock instant.
  [[nodiscard]] std::int64_t local_time(std::int64_t segment_ns) const;
  [[nodiscard]] std::uint64_t system_time(std::int64_t segment_ns) const;
  [[nodiscard]] std::uint64_t sync0_events() const;
  [[nodiscard]] std::uint32_t watchdog_expirations() const;
  // The process data of the last complete output SyncManager write (what the
  // master last sent) and the inputs last offered to the master's read.
  [[nodiscard]] ByteSpan last_outputs() const;
  [[nodiscard]] ByteSpan last_inputs() const;
  [[nodiscard]] const EscOptions& options() const;

 private:
  std::unique_ptr<detail::EscCore> core_;
};

}  // namespace sf::ethercat::slave
