// What the master knows about one slave: found by the scan, read from its
// ESC registers and SII, and decided by the configuration.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "sf/ethercat/master/process_image.hpp"
#include "sf/ethercat/registers.hpp"
#include "sf/ethercat/sii.hpp"

namespace sf::ethercat::master {

// ESC information registers 0x0000–0x0009 (ET1100 datasheet II §2.1–2.8).
struct EscInfo {
  std::uint8_t type = 0;
  std::uint8_t revision = 0;
  std::uint16_t build = 0;
  std::uint8_t fmmus = 0;
  std::uint8_t sync_managers = 0;
  std::uint8_t ram_kib = 0;
  std::uint8_t port_descriptor = 0;
  std::uint16_t features = 0;

  [[nodiscard]] bool dc_supported() const { return (features & reg::feature::kDistributedClocks) != 0; }
  [[nodiscard]] bool dc_64bit() const { return (features & reg::feature::kDc64Bit) != 0; }
};

// The standard mailbox (SII words 0x18–0x1C), as configured in SM0/SM1.
struct MailboxInfo {
  std::uint16_t rx_offset = 0;  // SM0: master → slave
  std::uint16_t rx_size = 0;
  std::uint16_t tx_offset = 0;  // SM1: slave → master
  std::uint16_t tx_size = 0;
  std::uint16_t protocols = 0;             // SII word 0x1C: bit 2 CoE
  std::uint8_t counter = 0;                // last counter used by the master (1..7)
  std::uint8_t last_received_counter = 0;  // to drop repeated slave messages

  [[nodiscard]] bool present() const { return rx_size > 0 && tx_size > 0; }
  [[nodiscard]] bool coe() const { return present() && (protocols & 0x0004U) != 0; }
};

// Distributed-clock measurements and settings of one slave.
struct DcInfo {
  bool supported = false;
  std::array<std::uint32_t, 4> port_receive_time{};  // 0x0900–0x090F, latched by BWR 0x0900
  std::uint64_t processing_unit_time = 0;            // 0x0918
  std::optional<std::size_t> parent;                 // position of the slave towards the master
  unsigned parent_port = 0;                          // the parent's port this slave hangs on
  std::uint32_t delay_ns = 0;                        // 0x0928, propagation delay from the reference
  std::uint64_t offset_ns = 0;                       // 0x0920, system time − local time
};

// An SDO download made during start-up (before the process data was
// configured), replayed when the slave comes back after a power loss.
struct StartupSdo {
  std::uint16_t index = 0;
  std::uint8_t subindex = 0;
  bool complete_access = false;
  Bytes data;
};

struct SlaveInfo {
  std::uint16_t position = 0;  // 0-based position in the segment
  std::uint16_t station = 0;   // configured station address (0x0010)
  std::uint16_t alias = 0;     // 0x0012
  EscInfo esc;
  DlStatus dl_status;
  SiiInfo sii;
  MailboxInfo mailbox;
  std::vector<StartupSdo> startup_sdos;
  PdoMapping pdo;
  SlaveImage image;
  DcInfo dc;
  AlStatus al_status;
  std::uint16_t al_status_code = 0;
  bool lost = false;             // stopped answering; the recovery brings it back
  std::uint32_t unanswered = 0;  // diagnoses in a row it did not answer

  [[nodiscard]] std::string name() const;  // SII name, else "slave <position>"
  [[nodiscard]] bool port_open(unsigned port) const {
    return dl_status.link(port) && !dl_status.loop_closed(port);
  }
};

}  // namespace sf::ethercat::master
