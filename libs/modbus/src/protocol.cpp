#include "sf/modbus/protocol.hpp"

#include <fmt/format.h>

namespace sf::modbus {

std::string_view to_string(Table table) {
  switch (table) {
    case Table::coils:
      return "coils";
    case Table::discrete_inputs:
      return "discrete_inputs";
    case Table::holding_registers:
      return "holding_registers";
    case Table::input_registers:
      return "input_registers";
  }
  return "table?";
}

std::string_view to_string(FunctionCode function) {
  switch (function) {
    case FunctionCode::read_coils:
      return "read_coils";
    case FunctionCode::read_discrete_inputs:
      return "read_discrete_inputs";
    case FunctionCode::read_holding_registers:
      return "read_holding_registers";
    case FunctionCode::read_input_registers:
      return "read_input_registers";
    case FunctionCode::write_single_coil:
      return "write_single_coil";
    case FunctionCode::write_single_register:
      return "write_single_register";
    case FunctionCode::write_multiple_coils:
      return "write_multiple_coils";
    case FunctionCode::write_multiple_registers:
      return "write_multiple_registers";
    case FunctionCode::mask_write_register:
      return "mask_write_register";
    case FunctionCode::read_write_multiple_registers:
      return "read_write_multiple_registers";
  }
  return {};
}

std::string_view to_string(ExceptionCode code) {
  switch (code) {
    case ExceptionCode::illegal_function:
      return "illegal_function";
    case ExceptionCode::illegal_data_address:
      return "illegal_data_address";
    case ExceptionCode::illegal_data_value:
      return "illegal_data_value";
    case ExceptionCode::server_device_failure:
      return "server_device_failure";
    case ExceptionCode::acknowledge:
      return "acknowledge";
    case ExceptionCode::server_device_busy:
      return "server_device_busy";
    case ExceptionCode::negative_acknowledge:
      return "negative_acknowledge";
    case ExceptionCode::memory_parity_error:
      return "memory_parity_error";
    case ExceptionCode::gateway_path_unavailable:
      return "gateway_path_unavailable";
    case ExceptionCode::gateway_target_failed_to_respond:
      return "gateway_target_failed_to_respond";
  }
  return "exception?";
}

bool is_served(std::uint8_t function) {
  return !to_string(static_cast<FunctionCode>(function)).empty();
}

std::string function_name(std::uint8_t function) {
  if (is_served(function)) {
    return std::string(to_string(static_cast<FunctionCode>(function)));
  }
  return fmt::format("function 0x{:02X}", function);
}

}  // namespace sf::modbus
