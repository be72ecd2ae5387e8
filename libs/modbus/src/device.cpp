#include "sf/modbus/device.hpp"

namespace sf::modbus {

std::optional<ExceptionCode> Device::before_request(const Request& /*request*/) {
  return std::nullopt;
}

void Device::after_write(const Request& /*request*/) {}

void Device::set_fault(Fault fault) {
  fault_.store(static_cast<std::uint16_t>((static_cast<unsigned>(fault.kind) << 8U) |
                                          static_cast<unsigned>(fault.exception)));
}

Fault Device::fault() const {
  const std::uint16_t word = fault_.load();
  return Fault{static_cast<Fault::Kind>(word >> 8U), static_cast<ExceptionCode>(word & 0xFFU)};
}

}  // namespace sf::modbus
