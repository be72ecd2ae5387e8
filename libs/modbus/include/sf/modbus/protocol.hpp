// Modbus vocabulary: the four data tables, the function codes we serve, the exception codes and
// the protocol's size limits (MODBUS Application Protocol Specification V1.1b3, "MB AP" below;
// MODBUS Messaging on TCP/IP Implementation Guide V1.0b, "MB TCP").
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

namespace sf::modbus {

// MB AP §4.3: the primary tables. Coils and holding registers are written by clients; discrete
// inputs and input registers only by the device itself.
enum class Table : std::uint8_t { coils, discrete_inputs, holding_registers, input_registers };

// MB AP §5.1 / §6: the data-access function codes. Any other code is answered with
// ExceptionCode::illegal_function.
enum class FunctionCode : std::uint8_t {
  read_coils = 0x01,                     // §6.1
  read_discrete_inputs = 0x02,           // §6.2
  read_holding_registers = 0x03,         // §6.3
  read_input_registers = 0x04,           // §6.4
  write_single_coil = 0x05,              // §6.5
  write_single_register = 0x06,          // §6.6
  write_multiple_coils = 0x0F,           // §6.11
  write_multiple_registers = 0x10,       // §6.12
  mask_write_register = 0x16,            // §6.16
  read_write_multiple_registers = 0x17,  // §6.17
};

// MB AP §7 (and 0x07, which libmodbus also names). A device may answer any request with one of
// these instead of data.
enum class ExceptionCode : std::uint8_t {
  illegal_function = 0x01,
  illegal_data_address = 0x02,
  illegal_data_value = 0x03,
  server_device_failure = 0x04,
  acknowledge = 0x05,
  server_device_busy = 0x06,
  negative_acknowledge = 0x07,
  memory_parity_error = 0x08,
  gateway_path_unavailable = 0x0A,
  gateway_target_failed_to_respond = 0x0B,
};

// Size limits, MB AP §6 (quantities) and §4.1 (PDU), MB TCP §3.1.3 (MBAP header).
inline constexpr std::uint16_t kMaxReadBits = 2000;           // 0x7D0, §6.1, §6.2
inline constexpr std::uint16_t kMaxWriteBits = 1968;          // 0x7B0, §6.11
inline constexpr std::uint16_t kMaxReadRegisters = 125;       // 0x7D, §6.3, §6.4, §6.17
inline constexpr std::uint16_t kMaxWriteRegisters = 123;      // 0x7B, §6.12
inline constexpr std::uint16_t kMaxReadWriteRegisters = 121;  // 0x79, the write part of §6.17
inline constexpr std::size_t kMaxPduLength = 253;
inline constexpr std::size_t kMbapLength = 7;  // transaction id, protocol id, length, unit id
inline constexpr std::size_t kMaxAduLength = kMbapLength - 1 + kMaxPduLength + 1;  // 260
// MB TCP §4.4.2: the unit id a client uses to address the server itself.
inline constexpr std::uint8_t kTcpUnitId = 0xFF;

// "read_holding_registers", "illegal_data_address", "coils": the names above.
std::string_view to_string(Table table);
std::string_view to_string(FunctionCode function);
std::string_view to_string(ExceptionCode code);
// The function's name, or "function 0x41" for a code we do not serve.
std::string function_name(std::uint8_t function);
// True for the codes FunctionCode names.
bool is_served(std::uint8_t function);

}  // namespace sf::modbus
