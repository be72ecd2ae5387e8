// ESC register map and the value types of its structured registers
// (ET1100 datasheet section II "Register description"; ETG.1000.4 §6).
// All registers are little-endian. Addresses are ADO values of physical
// (APxx/FPxx/BRx) datagrams.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

#include "sf/core/bytes.hpp"
#include "sf/core/result.hpp"

namespace sf::ethercat {

namespace reg {

// --- ESC information (datasheet II §2.1–2.8) ---
inline constexpr std::uint16_t kType = 0x0000;              // u8, e.g. 0x11 ET1100
inline constexpr std::uint16_t kRevision = 0x0001;          // u8
inline constexpr std::uint16_t kBuild = 0x0002;             // u16
inline constexpr std::uint16_t kFmmuCount = 0x0004;         // u8, FMMUs supported
inline constexpr std::uint16_t kSyncManagerCount = 0x0005;  // u8, SyncManagers supported
inline constexpr std::uint16_t kRamSize = 0x0006;           // u8, process RAM in KiB
inline constexpr std::uint16_t kPortDescriptor = 0x0007;    // u8, 2 bits per port (PortKind)
inline constexpr std::uint16_t kFeatures = 0x0008;          // u16, ESC features supported

// --- Station address (datasheet II §2.9–2.10) ---
inline constexpr std::uint16_t kStationAddress = 0x0010;  // u16, configured station address (FPxx)
inline constexpr std::uint16_t kStationAlias = 0x0012;    // u16, alias, loaded from SII word 4

// --- Write protection and reset (datasheet II §2.11–2.15) ---
inline constexpr std::uint16_t kRegisterWriteEnable = 0x0020;
inline constexpr std::uint16_t kRegisterWriteProtection = 0x0021;
inline constexpr std::uint16_t kEscWriteEnable = 0x0030;
inline constexpr std::uint16_t kEscWriteProtection = 0x0031;
inline constexpr std::uint16_t kEscResetEcat = 0x0040;
inline constexpr std::uint16_t kEscResetPdi = 0x0041;

// --- Data link layer (datasheet II §3) ---
inline constexpr std::uint16_t kDlControl = 0x0100;         // u32, forwarding and loop control
inline constexpr std::uint16_t kPhysicalRwOffset = 0x0108;  // u16, offset of the write part of xPRW
inline constexpr std::uint16_t kDlStatus = 0x0110;          // u16, see DlStatus

// --- Application layer (datasheet II §4) ---
inline constexpr std::uint16_t kAlControl = 0x0120;     // u16, requested state + error acknowledge
inline constexpr std::uint16_t kAlStatus = 0x0130;      // u16, current state + error indicator
inline constexpr std::uint16_t kAlStatusCode = 0x0134;  // u16, see al_status_codes.hpp
inline constexpr std::uint16_t kRunLedOverride = 0x0138;
inline constexpr std::uint16_t kErrLedOverride = 0x0139;

// --- PDI (datasheet II §5) ---
inline constexpr std::uint16_t kPdiControl = 0x0140;        // u8, PDI type (loaded from SII word 0)
inline constexpr std::uint16_t kEscConfiguration = 0x0141;  // u8
inline constexpr std::uint16_t kPdiInformation = 0x014E;    // u16
inline constexpr std::uint16_t kPdiConfiguration = 0x0150;  // u8..u16, SII word 1

// --- Interrupts (datasheet II §6) ---
inline constexpr std::uint16_t kEcatEventMask = 0x0200;     // u16
inline constexpr std::uint16_t kAlEventMask = 0x0204;       // u32, PDI0 / AL event mask
inline constexpr std::uint16_t kEcatEventRequest = 0x0210;  // u16, mirrored into every datagram IRQ
inline constexpr std::uint16_t kAlEventRequest = 0x0220;    // u32

// --- Error counters (datasheet II §7) ---
inline constexpr std::uint16_t kRxErrorCounter = 0x0300;  // 2 bytes per port: invalid frame, RX error
inline constexpr std::uint16_t kForwardedRxErrorCounter = 0x0308;     // u8 per port
inline constexpr std::uint16_t kProcessingUnitErrorCounter = 0x030C;  // u8
inline constexpr std::uint16_t kPdiErrorCounter = 0x030D;             // u8
inline constexpr std::uint16_t kPdiErrorCode = 0x030E;                // u8
inline constexpr std::uint16_t kLostLinkCounter = 0x0310;             // u8 per port
constexpr std::uint16_t rx_error_counter(unsigned port) {
  return static_cast<std::uint16_t>(kRxErrorCounter + 2U * port);
}
constexpr std::uint16_t lost_link_counter(unsigned port) {
  return static_cast<std::uint16_t>(kLostLinkCounter + port);
}

// --- Watchdogs (datasheet II §8) ---
inline constexpr std::uint16_t kWatchdogDivider = 0x0400;             // u16, in 40 ns units, minus 2
inline constexpr std::uint16_t kWatchdogTimePdi = 0x0410;             // u16, in divider units
inline constexpr std::uint16_t kWatchdogTimeProcessData = 0x0420;     // u16, in divider units
inline constexpr std::uint16_t kWatchdogStatusProcessData = 0x0440;   // u16, bit 0: 1 = active/reloaded
inline constexpr std::uint16_t kWatchdogCounterProcessData = 0x0442;  // u8, expirations
inline constexpr std::uint16_t kWatchdogCounterPdi = 0x0443;          // u8, expirations
// Default divider 2498 → 100 µs watchdog unit; default process-data time 1000 → 100 ms.
inline constexpr std::uint16_t kDefaultWatchdogDivider = 2498;
inline constexpr std::uint16_t kDefaultWatchdogTime = 1000;

// --- SII EEPROM interface (datasheet II §9, registers 0x0500–0x050F) ---
inline constexpr std::uint16_t kSiiConfiguration = 0x0500;  // u8, bit 0: EEPROM offered to PDI
inline constexpr std::uint16_t kSiiPdiAccess = 0x0501;      // u8, bit 0: PDI owns the EEPROM
inline constexpr std::uint16_t kSiiControlStatus = 0x0502;  // u16, see sii_control
inline constexpr std::uint16_t kSiiAddress = 0x0504;        // u32, word address
inline constexpr std::uint16_t kSiiData = 0x0508;           // 4 or 8 bytes read / 2 bytes written

namespace sii_control {
inline constexpr std::uint16_t kWriteEnable = 1U << 0;  // ECAT write enable (self-clearing)
inline constexpr std::uint16_t kEmulation = 1U << 5;    // EEPROM emulated by the PDI
inline constexpr std::uint16_t kRead8Bytes = 1U << 6;   // 1: a read returns 8 bytes, 0: 4 bytes
inline constexpr std::uint16_t kTwoAddressBytes = 1U << 7;
inline constexpr std::uint16_t kCommandMask = 0x0700;  // bits 10:8
inline constexpr std::uint16_t kCommandRead = 0x0100;
inline constexpr std::uint16_t kCommandWrite = 0x0200;
inline constexpr std::uint16_t kCommandReload = 0x0400;
inline constexpr std::uint16_t kChecksumError = 1U << 11;     // configuration area CRC wrong
inline constexpr std::uint16_t kLoadError = 1U << 12;         // device information not loaded
inline constexpr std::uint16_t kAcknowledgeError = 1U << 13;  // missing acknowledge or invalid command
inline constexpr std::uint16_t kWriteEnableError = 1U << 14;  // write without write enable
inline constexpr std::uint16_t kBusy = 1U << 15;
}  // namespace sii_control

// --- MII management (datasheet II §10) ---
inline constexpr std::uint16_t kMiiControlStatus = 0x0510;
inline constexpr std::uint16_t kPhyAddress = 0x0512;
inline constexpr std::uint16_t kPhyRegisterAddress = 0x0513;
inline constexpr std::uint16_t kPhyData = 0x0514;

// --- FMMUs (datasheet II §11): 16 bytes each from 0x0600 ---
inline constexpr std::uint16_t kFmmuBase = 0x0600;
inline constexpr std::size_t kFmmuSize = 16;
inline constexpr std::size_t kMaxFmmus = 16;
constexpr std::uint16_t fmmu(unsigned n) {
  return static_cast<std::uint16_t>(kFmmuBase + kFmmuSize * n);
}

// --- SyncManagers (datasheet II §12): 8 bytes each from 0x0800 ---
inline constexpr std::uint16_t kSyncManagerBase = 0x0800;
inline constexpr std::size_t kSyncManagerSize = 8;
inline constexpr std::size_t kMaxSyncManagers = 16;
constexpr std::uint16_t sync_manager(unsigned n) {
  return static_cast<std::uint16_t>(kSyncManagerBase + kSyncManagerSize * n);
}
// Offsets inside one SyncManager block.
inline constexpr std::uint16_t kSmStart = 0;
inline constexpr std::uint16_t kSmLength = 2;
inline constexpr std::uint16_t kSmControl = 4;
inline constexpr std::uint16_t kSmStatus = 5;
inline constexpr std::uint16_t kSmActivate = 6;
inline constexpr std::uint16_t kSmPdiControl = 7;

// --- Distributed clocks, receive times and time loop (datasheet II §13.1–13.3) ---
inline constexpr std::uint16_t kDcReceiveTimePort0 = 0x0900;  // u32; a write here latches all ports
inline constexpr std::uint16_t kDcReceiveTimePort1 = 0x0904;  // u32
inline constexpr std::uint16_t kDcReceiveTimePort2 = 0x0908;  // u32
inline constexpr std::uint16_t kDcReceiveTimePort3 = 0x090C;  // u32
constexpr std::uint16_t dc_receive_time(unsigned port) {
  return static_cast<std::uint16_t>(kDcReceiveTimePort0 + 4U * port);
}
inline constexpr std::uint16_t kDcSystemTime = 0x0910;                 // u64; ARMW/FRMW here distributes time
inline constexpr std::uint16_t kDcReceiveTimeProcessingUnit = 0x0918;  // u64, local time at port 0
inline constexpr std::uint16_t kDcSystemTimeOffset = 0x0920;           // u64, system − local
inline constexpr std::uint16_t kDcSystemTimeDelay = 0x0928;       // u32, propagation delay from reference
inline constexpr std::uint16_t kDcSystemTimeDifference = 0x092C;  // u32, bit 31: local < received
inline constexpr std::uint16_t kDcSpeedCounterStart = 0x0930;     // u16, drift compensation bandwidth
inline constexpr std::uint16_t kDcSpeedCounterDiff = 0x0932;      // i16
inline constexpr std::uint16_t kDcSystemTimeDiffFilterDepth = 0x0934;  // u8
inline constexpr std::uint16_t kDcSpeedCounterFilterDepth = 0x0935;    // u8
inline constexpr std::uint16_t kDcReceiveTimeLatchMode = 0x0936;       // u8

// --- DC cyclic unit / SYNC signals (datasheet II §13.4) ---
inline constexpr std::uint16_t kDcCyclicUnitControl = 0x0980;  // u8
inline constexpr std::uint16_t kDcActivation = 0x0981;         // u8: bit0 cyclic op, bit1 SYNC0, bit2 SYNC1
inline constexpr std::uint16_t kDcPulseLength = 0x0982;        // u16, in 10 ns units
inline constexpr std::uint16_t kDcActivationStatus = 0x0984;
inline constexpr std::uint16_t kDcSync0Status = 0x098E;
inline constexpr std::uint16_t kDcSync1Status = 0x098F;
inline constexpr std::uint16_t kDcStartTimeCyclic = 0x0990;  // u64, SYNC0 start time (system time)
inline constexpr std::uint16_t kDcNextSync1Pulse = 0x0998;   // u64
inline constexpr std::uint16_t kDcSync0CycleTime = 0x09A0;   // u32, ns
inline constexpr std::uint16_t kDcSync1CycleTime = 0x09A4;   // u32, ns
inline constexpr std::uint8_t kDcActivationCyclic = 1U << 0;
inline constexpr std::uint8_t kDcActivationSync0 = 1U << 1;
inline constexpr std::uint8_t kDcActivationSync1 = 1U << 2;

// --- DC latch unit (datasheet II §13.5) ---
inline constexpr std::uint16_t kDcLatch0Control = 0x09A8;
inline constexpr std::uint16_t kDcLatch1Control = 0x09A9;
inline constexpr std::uint16_t kDcLatch0Status = 0x09AE;
inline constexpr std::uint16_t kDcLatch1Status = 0x09AF;
inline constexpr std::uint16_t kDcLatch0PositiveEdge = 0x09B0;  // u64
inline constexpr std::uint16_t kDcLatch0NegativeEdge = 0x09B8;  // u64
inline constexpr std::uint16_t kDcLatch1PositiveEdge = 0x09C0;  // u64
inline constexpr std::uint16_t kDcLatch1NegativeEdge = 0x09C8;  // u64

// --- ESC specific and process RAM (datasheet II §14–15) ---
inline constexpr std::uint16_t kPowerOnValues = 0x0E00;      // u16 (ET1100)
inline constexpr std::uint16_t kDigitalOutputData = 0x0F00;  // u32
inline constexpr std::uint16_t kProcessRam = 0x1000;         // process data RAM (and mailbox buffers)

// ESC features supported (0x0008) bits.
namespace feature {
inline constexpr std::uint16_t kFmmuByteOriented = 1U << 0;  // 0: bit-oriented FMMUs, 1: byte-oriented
inline constexpr std::uint16_t kDistributedClocks = 1U << 2;
inline constexpr std::uint16_t kDc64Bit = 1U << 3;
inline constexpr std::uint16_t kEbusLowJitter = 1U << 4;
inline constexpr std::uint16_t kEnhancedLinkDetectionEbus = 1U << 5;
inline constexpr std::uint16_t kEnhancedLinkDetectionMii = 1U << 6;
inline constexpr std::uint16_t kSeparateFcsErrors = 1U << 7;
inline constexpr std::uint16_t kEnhancedDcSync = 1U << 8;
inline constexpr std::uint16_t kLrwNotSupported = 1U << 9;  // note the inverted sense
inline constexpr std::uint16_t kRwNotSupported = 1U << 10;  // BRW/APRW/FPRW not supported
inline constexpr std::uint16_t kFixedFmmuSmConfig = 1U << 11;
}  // namespace feature

// AL control (0x0120) / AL status (0x0130) bits beyond the 4-bit state.
inline constexpr std::uint16_t kAlStateMask = 0x000F;
inline constexpr std::uint16_t kAlErrorFlag = 0x0010;  // control: acknowledge; status: error indicator
inline constexpr std::uint16_t kAlDeviceIdentification = 0x0020;

}  // namespace reg

// Port descriptor (0x0007): 2 bits per port.
enum class PortKind : std::uint8_t { not_implemented = 0, not_configured = 1, ebus = 2, mii = 3 };
constexpr PortKind port_kind(std::uint8_t descriptor, unsigned port) {
  return static_cast<PortKind>((static_cast<unsigned>(descriptor) >> (2U * port)) & 0x3U);
}

// ETG.1000.6 §6.4.1 / datasheet II §4: the EtherCAT state machine states as
// they appear in AL control/status bits 3:0.
enum class AlState : std::uint8_t { Init = 1, PreOp = 2, Bootstrap = 3, SafeOp = 4, Op = 8 };
inline constexpr std::uint8_t kAlStateErrorFlag = 0x10;

// The order of the states for "higher" and "lower" transitions (ETG.1000.6 §6.4.1): INIT < PREOP
// < SAFEOP < OP, with BOOT beside PREOP (it is entered and left only through INIT).
constexpr int rank(AlState s) {
  switch (s) {
    case AlState::Init:
      return 0;
    case AlState::PreOp:
    case AlState::Bootstrap:
      return 1;
    case AlState::SafeOp:
      return 2;
    case AlState::Op:
      return 3;
  }
  return 0;
}

// "INIT", "PREOP", "BOOT", "SAFEOP", "OP".
std::string_view to_string(AlState s);
// Accepts the names above (case-insensitive, also "PRE-OP", "SAFE-OP", "BOOTSTRAP").
std::optional<AlState> al_state_from_string(std::string_view name);
// The state in bits 3:0 of an AL control/status value, if it is a valid one.
std::optional<AlState> al_state_from_bits(std::uint16_t value);

// AL status register (0x0130) as a value.
struct AlStatus {
  std::uint8_t state_bits = 1;  // bits 3:0 (kept raw: an ESC may report an invalid value)
  bool error = false;           // bit 4
  bool id_loaded = false;       // bit 5, device identification value loaded

  [[nodiscard]] std::optional<AlState> state() const { return al_state_from_bits(state_bits); }
  [[nodiscard]] std::uint16_t encode() const;
  static AlStatus decode(std::uint16_t value);
  static AlStatus of(AlState s, bool error = false) {
    return AlStatus{static_cast<std::uint8_t>(s), error, false};
  }
  // "SAFEOP + ERROR", "0x7 (invalid)".
  [[nodiscard]] std::string to_string() const;
  bool operator==(const AlStatus&) const = default;
};

// AL control register (0x0120) as a value.
struct AlControl {
  std::uint8_t state_bits = 1;
  bool acknowledge = false;  // bit 4: error indication acknowledge
  bool request_id = false;   // bit 5: device identification request

  [[nodiscard]] std::optional<AlState> state() const { return al_state_from_bits(state_bits); }
  [[nodiscard]] std::uint16_t encode() const;
  static AlControl decode(std::uint16_t value);
  static AlControl of(AlState s, bool acknowledge = false) {
    return AlControl{static_cast<std::uint8_t>(s), acknowledge, false};
  }
  bool operator==(const AlControl&) const = default;
};

// ESC DL status (0x0110), datasheet II §3.3: per port a physical-link bit
// (4+p), a loop bit (8+2p, 1 = closed) and a communication bit (9+2p).
struct DlStatus {
  std::uint16_t value = 0;

  static constexpr std::uint16_t kPdiOperational = 1U << 0;  // EEPROM loaded, PDI running
  static constexpr std::uint16_t kPdiWatchdogReloaded = 1U << 1;
  static constexpr std::uint16_t kEnhancedLinkDetection = 1U << 2;
  static constexpr std::uint16_t link_bit(unsigned port) {
    return static_cast<std::uint16_t>(1U << (4U + port));
  }
  static constexpr std::uint16_t loop_bit(unsigned port) {
    return static_cast<std::uint16_t>(1U << (8U + 2U * port));
  }
  static constexpr std::uint16_t communication_bit(unsigned port) {
    return static_cast<std::uint16_t>(1U << (9U + 2U * port));
  }

  [[nodiscard]] bool pdi_operational() const { return (value & kPdiOperational) != 0; }
  [[nodiscard]] bool link(unsigned port) const { return (value & link_bit(port)) != 0; }
  [[nodiscard]] bool loop_closed(unsigned port) const { return (value & loop_bit(port)) != 0; }
  [[nodiscard]] bool communication(unsigned port) const { return (value & communication_bit(port)) != 0; }

  void set(std::uint16_t bit, bool on) {
    value = static_cast<std::uint16_t>(on ? (value | bit) : (value & ~bit));
  }
  void set_link(unsigned port, bool on) { set(link_bit(port), on); }
  void set_loop_closed(unsigned port, bool on) { set(loop_bit(port), on); }
  void set_communication(unsigned port, bool on) { set(communication_bit(port), on); }
  // A port with a link and an open loop forwards to a neighbour; the usual
  // encoding of "link up, communication established, loop open".
  void set_port_open(unsigned port) {
    set_link(port, true);
    set_communication(port, true);
    set_loop_closed(port, false);
  }
  // A port with no link closes its loop (frames return through it).
  void set_port_closed(unsigned port) {
    set_link(port, false);
    set_communication(port, false);
    set_loop_closed(port, true);
  }
  bool operator==(const DlStatus&) const = default;
};

// FMMU type register (+0x0B) bits.
inline constexpr std::uint8_t kFmmuRead = 0x01;   // maps for reads (LRD, read part of LRW)
inline constexpr std::uint8_t kFmmuWrite = 0x02;  // maps for writes (LWR, write part of LRW)

// One FMMU (datasheet II §11, 16 bytes at 0x0600 + 16·n): maps a logical
// address range bit-exactly onto physical ESC memory.
struct FmmuConfig {
  static constexpr std::size_t kSize = 16;

  std::uint32_t logical_start = 0;      // +0x00
  std::uint16_t length = 0;             // +0x04, bytes spanned in logical space
  std::uint8_t logical_start_bit = 0;   // +0x06, 0..7
  std::uint8_t logical_stop_bit = 7;    // +0x07, 0..7
  std::uint16_t physical_start = 0;     // +0x08
  std::uint8_t physical_start_bit = 0;  // +0x0A, 0..7
  std::uint8_t type = 0;                // +0x0B, kFmmuRead | kFmmuWrite
  bool active = false;                  // +0x0C bit 0

  [[nodiscard]] bool reads() const { return (type & kFmmuRead) != 0; }
  [[nodiscard]] bool writes() const { return (type & kFmmuWrite) != 0; }
  // Byte-aligned, active mapping of `size` bytes (what process-data mappings use).
  static FmmuConfig bytes(std::uint32_t logical, std::uint16_t physical, std::uint16_t size,
                          std::uint8_t fmmu_type);

  [[nodiscard]] std::array<std::uint8_t, kSize> encode() const;
  // Needs at least kSize bytes; bit numbers above 7 are rejected.
  static Result<FmmuConfig> decode(ByteSpan bytes);
  bool operator==(const FmmuConfig&) const = default;
};

// SyncManager control register (+4) fields, datasheet II §12.
enum class SyncManagerMode : std::uint8_t { buffered = 0b00, mailbox = 0b10 };  // bits 1:0
// Bits 3:2, as seen from the master: read = ECAT reads / PDI writes (inputs,
// mailbox in), write = ECAT writes / PDI reads (outputs, mailbox out).
enum class SyncManagerDirection : std::uint8_t { read = 0b00, write = 0b01 };

namespace sm {
inline constexpr std::uint8_t kModeMask = 0x03;
inline constexpr std::uint8_t kDirectionMask = 0x0C;
inline constexpr std::uint8_t kEcatInterrupt = 1U << 4;  // control: IRQ in ECAT event request
inline constexpr std::uint8_t kPdiInterrupt = 1U << 5;   // control: IRQ in AL event request
inline constexpr std::uint8_t kWatchdog = 1U << 6;       // control: write triggers the PD watchdog
// Status register (+5).
inline constexpr std::uint8_t kStatusWriteEvent = 1U << 0;
inline constexpr std::uint8_t kStatusReadEvent = 1U << 1;
inline constexpr std::uint8_t kStatusMailboxFull = 1U << 3;
inline constexpr std::uint8_t kStatusBufferMask = 0x30;  // 3-buffer: last written buffer, 3 = none
inline constexpr std::uint8_t kStatusReadBufferOpen = 1U << 6;
inline constexpr std::uint8_t kStatusWriteBufferOpen = 1U << 7;
// Activate register (+6).
inline constexpr std::uint8_t kActivateEnable = 1U << 0;
inline constexpr std::uint8_t kActivateRepeat = 1U << 1;
inline constexpr std::uint8_t kActivateLatchEcat = 1U << 6;
inline constexpr std::uint8_t kActivateLatchPdi = 1U << 7;
// PDI control register (+7).
inline constexpr std::uint8_t kPdiDeactivate = 1U << 0;
inline constexpr std::uint8_t kPdiRepeatAck = 1U << 1;
}  // namespace sm

// One SyncManager (datasheet II §12, 8 bytes at 0x0800 + 8·n).
struct SyncManagerConfig {
  static constexpr std::size_t kSize = 8;

  std::uint16_t start = 0;       // +0, physical start address
  std::uint16_t length = 0;      // +2, bytes
  std::uint8_t control = 0;      // +4
  std::uint8_t status = 0;       // +5, read-only for the master
  std::uint8_t activate = 0;     // +6
  std::uint8_t pdi_control = 0;  // +7, read-only for the master

  [[nodiscard]] SyncManagerMode mode() const;  // bits 1:0 (01/11 reserved map to buffered)
  [[nodiscard]] bool mode_valid() const { return (control & 0x01U) == 0; }
  [[nodiscard]] SyncManagerDirection direction() const;  // bits 3:2 (1x reserved map to write)
  [[nodiscard]] bool enabled() const { return (activate & sm::kActivateEnable) != 0; }
  [[nodiscard]] bool repeat() const { return (activate & sm::kActivateRepeat) != 0; }
  [[nodiscard]] bool mailbox_full() const { return (status & sm::kStatusMailboxFull) != 0; }
  [[nodiscard]] bool contains(std::uint16_t address) const {
    return address >= start && address - start < length;
  }

  // A configuration as a master writes it; control gets the mode, the
  // direction and, for mailboxes, the PDI interrupt (bit 5), as usual.
  static SyncManagerConfig make(std::uint16_t start, std::uint16_t length, SyncManagerMode mode,
                                SyncManagerDirection direction, bool enable = true);

  [[nodiscard]] std::array<std::uint8_t, kSize> encode() const;
  static Result<SyncManagerConfig> decode(ByteSpan bytes);  // needs at least kSize bytes
  bool operator==(const SyncManagerConfig&) const = default;
};

}  // namespace sf::ethercat
