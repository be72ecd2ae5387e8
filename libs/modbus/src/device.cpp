#include "sf/modbus/device.hpp"

namespace sf::modbus {

std::optional<ExceptionCode> Device::before_request(const Request& /*request*/) {
  return std::nullopt;
}

void Device::after_write(const Request& /*request*/) {}

}  // namespace sf::modbus
