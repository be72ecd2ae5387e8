// The ESC register area 0x0000–0x0FFF as the EtherCAT side sees it: which
// bits of each byte the master may write (ET1100 datasheet II, "ECAT" access
// column of every register table) and which registers have side effects when
// written or read. Built once as tables so the per-byte path has no branches
// on addresses and no lookups.
#pragma once

#include <array>
#include <cstdint>

namespace sf::ethercat::slave::detail {

inline constexpr std::size_t kRegisterAreaSize = 0x1000;
inline constexpr std::uint16_t kUserRam = 0x0F80;  // not covered by register write protection

// Registers with side effects. A datagram collects the groups it touched and
// the ESC runs each handler once afterwards.
enum class RegGroup : std::uint8_t {
  none = 0,
  register_write_enable,   // 0x0020
  esc_write_enable,        // 0x0030
  esc_reset,               // 0x0040
  dl_control,              // 0x0100–0x0103
  al_control,              // 0x0120–0x0121
  al_status,               // 0x0130 (read clears the AL status event)
  error_counters,          // 0x0300–0x0313 (write clears)
  watchdog_config,         // 0x0400–0x0401, 0x0420–0x0421
  watchdog_counters,       // 0x0442–0x0443 (write clears)
  sii_control,             // 0x0502–0x0503
  sii_registers,           // 0x0504–0x050F (refreshed on read)
  fmmu,                    // 0x0600–0x06FF
  sm_config,               // 0x0800+8n .. +4 (writable only while the SM is disabled)
  sm_activate,             // 0x0800+8n+6
  sm_status,               // 0x0800+8n+5 (read-only)
  dc_receive_time,         // 0x0900–0x0903: a write latches the receive times
  dc_system_time,          // 0x0910–0x0917: write feeds the time control loop
  dc_speed_counter_start,  // 0x0930–0x0931: write resets the filters
  dc_cyclic,               // 0x0980–0x0981, 0x0990–0x0997, 0x09A0–0x09A7
  dc_sync_status,          // 0x098E–0x098F (read clears in acknowledge mode)
  count_
};

struct RegisterMap {
  std::array<std::uint8_t, kRegisterAreaSize> write_mask{};
  std::array<RegGroup, kRegisterAreaSize> group{};
};

// The table for an ESC with `fmmus` FMMUs and `sync_managers` SyncManagers
// (registers of units that do not exist read 0 and ignore writes).
const RegisterMap& register_map(unsigned fmmus, unsigned sync_managers);

}  // namespace sf::ethercat::slave::detail
