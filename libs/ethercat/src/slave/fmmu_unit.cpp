#include "fmmu_unit.hpp"

#include <algorithm>

namespace sf::ethercat::slave::detail {

void FmmuUnit::power_on(EscMemory& m, unsigned count) {
  count_ = std::min<unsigned>(count, reg::kMaxFmmus);
  for (unsigned n = 0; n < count_; ++n) {
    std::fill(m.at(reg::fmmu(n)), m.at(reg::fmmu(n) + FmmuConfig::kSize), std::uint8_t{0});
  }
  valid_.fill(false);
  rebuild();
}

void FmmuUnit::on_written(const EscMemory& m, unsigned n) {
  valid_[n] = false;
  auto cfg = FmmuConfig::decode(ByteSpan(m.at(reg::fmmu(n)), FmmuConfig::kSize));
  if (cfg && cfg->active && cfg->length > 0 && (cfg->reads() || cfg->writes())) {
    // Logical range: from start byte/bit to the stop bit of the last byte
    // (datasheet II Table 80–84: length counts bytes from start to stop).
    const std::uint64_t first = std::uint64_t{cfg->logical_start} * 8U + cfg->logical_start_bit;
    const std::uint64_t last =
        (std::uint64_t{cfg->logical_start} + cfg->length - 1U) * 8U + cfg->logical_stop_bit;
    if (last >= first) {
      mappings_[n] = FmmuMapping{first, last - first + 1U,
                                 std::uint32_t{cfg->physical_start} * 8U + cfg->physical_start_bit,
                                 cfg->reads(), cfg->writes()};
      valid_[n] = true;
    }
  }
  rebuild();
}

void FmmuUnit::rebuild() {
  active_count_ = 0;
  for (unsigned n = 0; n < count_; ++n) {
    if (valid_[n]) {
      active_[active_count_++] = mappings_[n];
    }
  }
}

}  // namespace sf::ethercat::slave::detail
