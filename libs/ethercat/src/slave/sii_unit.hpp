// The SII EEPROM interface of the ESC (ET1100 datasheet II §3.45, registers
// 0x0500–0x050F; section I §11 "SII EEPROM"). The EEPROM content is the image
// encode_sii() made of the device's SiiInfo, padded with 0xFF (erased
// EEPROM) to its declared size. Commands keep the busy bit for an emulated
// time; bad addresses and commands set the error bits the datasheet defines.
#pragma once

#include <chrono>
#include <cstdint>

#include "esc_memory.hpp"
#include "sf/core/bytes.hpp"

namespace sf::ethercat::slave::detail {

struct SiiTiming {
  std::chrono::nanoseconds busy_time{};
  unsigned busy_polls = 1;
};

class SiiUnit {
 public:
  // `image` is padded to a power-of-two size of at least 1 KiBit.
  void load(Bytes image, bool read_8_bytes, SiiTiming timing);
  // Power-on: registers 0x0500–0x050F to defaults, then the ESC
  // configuration area (words 0–7) into 0x0012, 0x0140, 0x0150, 0x0982 if its
  // checksum is right (else the checksum error bit stays set).
  void power_on(EscMemory& m);
  // The master wrote 0x0502/0x0503; `written` is the 16-bit value it wrote.
  void on_control_written(EscMemory& m, std::uint16_t written, std::int64_t now_ns);
  // Before an ECAT read of 0x0502–0x050F (`status_read`: the status word is
  // read): completes a command whose time is up or whose status was polled
  // often enough.
  void before_read(EscMemory& m, std::int64_t now_ns, bool status_read);
  // Timer path: completes a command whose time is up.
  void poll(EscMemory& m, std::int64_t now_ns);

  [[nodiscard]] bool busy() const { return busy_; }
  [[nodiscard]] const Bytes& image() const { return image_; }
  [[nodiscard]] std::size_t words() const { return image_.size() / 2; }

 private:
  void complete(EscMemory& m);
  void set_status(EscMemory& m, std::uint16_t set, std::uint16_t clear);

  Bytes image_;
  bool read8_ = true;
  SiiTiming timing_;
  bool busy_ = false;
  std::uint16_t command_ = 0;
  std::uint32_t address_ = 0;
  std::uint16_t write_word_ = 0;
  std::int64_t deadline_ns_ = 0;
  unsigned polls_ = 0;
};

}  // namespace sf::ethercat::slave::detail
