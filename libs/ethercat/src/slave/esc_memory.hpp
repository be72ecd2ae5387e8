// The ESC's 64 KiB address space as one flat array: registers and process
// RAM are the state the master sees, so units keep their state here (plus
// shadow state where the hardware has hidden state, e.g. 3-buffer indices).
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <type_traits>

#include "sf/core/bytes.hpp"

namespace sf::ethercat::slave::detail {

struct EscMemory {
  static constexpr std::size_t kSize = 0x10000;
  std::array<std::uint8_t, kSize> bytes{};

  template <typename T>
  requires std::is_arithmetic_v<T>
  [[nodiscard]] T get(std::uint32_t address) const {
    return address + sizeof(T) <= kSize ? load_le<T>(bytes.data() + address) : T{};
  }
  template <typename T>
  requires std::is_arithmetic_v<T>
  void put(std::uint32_t address, T value) {
    if (address + sizeof(T) <= kSize) {
      store_le<T>(bytes.data() + address, value);
    }
  }
  [[nodiscard]] std::uint8_t* at(std::uint32_t address) { return bytes.data() + address; }
  [[nodiscard]] const std::uint8_t* at(std::uint32_t address) const { return bytes.data() + address; }
  void set_bits(std::uint32_t address, std::uint8_t bits, bool on) {
    bytes[address] = static_cast<std::uint8_t>(on ? (bytes[address] | bits) : (bytes[address] & ~bits));
  }
};

}  // namespace sf::ethercat::slave::detail
