// What the kinds of device logic share (device_logic.hpp): fault texts, stop
// reasons, operation parameters.
#include "device_logic.hpp"

#include <cmath>

#include <fmt/format.h>

namespace sf::factory::gateway {

std::string describe(line::FaultCode code) {
  return fmt::format("{} (PLC fault {})", line::to_string(code), static_cast<int>(code));
}

std::string latched_fault(const PlcIo& io, std::uint16_t fault_input, std::uint16_t fault_code_register) {
  if (!io.input(fault_input)) {
    return {};
  }
  return describe(static_cast<line::FaultCode>(io.input_register(fault_code_register)));
}

StopReason plc_stop_reason(const std::string& what, line::FaultCode code) {
  return StopReason{static_cast<std::int32_t>(code), fmt::format("{}: {}", what, describe(code)), {}};
}

bool box_read(const Operation& op, const PlcIo& io, std::uint16_t reader) {
  const std::uint16_t read = io.steady_input_register(reader);
  const auto box = op.param("box");
  return read != 0 && box && *box == read;
}

Result<std::int64_t> int_param(const Operation& op, std::string_view name, std::int64_t lo, std::int64_t hi) {
  auto value = op.param(name);
  if (!value) {
    return make_error(Errc::invalid_argument, fmt::format("{} needs the parameter '{}'", op.type, name));
  }
  if (!std::isfinite(*value) || *value != std::floor(*value) || *value < static_cast<double>(lo) ||
      *value > static_cast<double>(hi)) {
    return make_error(Errc::invalid_argument, fmt::format("{}: '{}' = {} is not a whole number in {}..{}",
                                                          op.type, name, *value, lo, hi));
  }
  return static_cast<std::int64_t>(*value);
}

}  // namespace sf::factory::gateway
