// Bit-granular copies for FMMU and PDO mappings (LSB first within a byte,
// as EtherCAT numbers bits).
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstring>

namespace sf::ethercat::slave::detail {

inline void copy_bits(const std::uint8_t* src, std::size_t src_bit, std::uint8_t* dst, std::size_t dst_bit,
                      std::size_t bits) {
  if (src_bit % 8 == 0 && dst_bit % 8 == 0 && bits % 8 == 0) {
    std::memcpy(dst + dst_bit / 8, src + src_bit / 8, bits / 8);
    return;
  }
  for (std::size_t i = 0; i < bits; ++i) {
    const std::size_t s = src_bit + i;
    const std::size_t d = dst_bit + i;
    const bool on = ((src[s / 8] >> (s % 8)) & 1U) != 0;
    const auto mask = static_cast<std::uint8_t>(1U << (d % 8));
    dst[d / 8] = static_cast<std::uint8_t>(on ? (dst[d / 8] | mask) : (dst[d / 8] & ~mask));
  }
}

}  // namespace sf::ethercat::slave::detail
