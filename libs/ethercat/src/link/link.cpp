// Helpers shared by every Link implementation.
#include "sf/ethercat/link.hpp"

namespace sf::ethercat {

bool is_ethercat_frame(ByteSpan frame) {
  if (frame.size() < kEthernetHeaderSize) {
    return false;
  }
  auto type_at = [&](std::size_t i) { return static_cast<std::uint16_t>((frame[i] << 8U) | frame[i + 1]); };
  std::uint16_t type = type_at(12);
  if (type == kVlanEtherType && frame.size() >= kEthernetHeaderSize + kVlanTagSize) {
    type = type_at(12 + kVlanTagSize);
  }
  return type == kEtherType;
}

}  // namespace sf::ethercat
