// Big-endian fields of Modbus frames (MB AP §4.2: "MODBUS uses a 'big-Endian' representation").
#pragma once

#include <cstdint>

namespace sf::modbus::wire {

inline std::uint16_t load_be16(const std::uint8_t* p) {
  return static_cast<std::uint16_t>((static_cast<unsigned>(p[0]) << 8U) | p[1]);
}

inline void store_be16(std::uint8_t* p, std::uint16_t value) {
  p[0] = static_cast<std::uint8_t>(value >> 8U);
  p[1] = static_cast<std::uint8_t>(value & 0xFFU);
}

// MB AP §6.5: the two values of a write_single_coil request.
inline constexpr std::uint16_t kCoilOn = 0xFF00;
inline constexpr std::uint16_t kCoilOff = 0x0000;

}  // namespace sf::modbus::wire
