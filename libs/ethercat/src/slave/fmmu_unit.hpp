// FMMUs (ET1100 datasheet section I §7, registers II §3.47 at 0x0600 + 16·n):
// each maps a bit-exact range of the 4 GiB logical address space onto ESC
// memory for logical commands. Decoded once when the master writes the
// registers; logical datagrams then walk the short list of active ones.
#pragma once

#include <array>
#include <cstdint>
#include <span>

#include "esc_memory.hpp"
#include "sf/ethercat/registers.hpp"

namespace sf::ethercat::slave::detail {

struct FmmuMapping {
  std::uint64_t logical_bit = 0;  // first mapped bit in logical space (address·8 + bit)
  std::uint64_t bits = 0;         // number of mapped bits
  std::uint32_t physical_bit = 0;
  bool read = false;
  bool write = false;
};

class FmmuUnit {
 public:
  void power_on(EscMemory& m, unsigned count);
  void on_written(const EscMemory& m, unsigned n);
  [[nodiscard]] std::span<const FmmuMapping> active() const { return {active_.data(), active_count_}; }
  [[nodiscard]] unsigned count() const { return count_; }

 private:
  void rebuild();

  std::array<FmmuMapping, reg::kMaxFmmus> mappings_{};
  std::array<bool, reg::kMaxFmmus> valid_{};
  std::array<FmmuMapping, reg::kMaxFmmus> active_{};
  std::size_t active_count_ = 0;
  unsigned count_ = 0;
};

}  // namespace sf::ethercat::slave::detail
