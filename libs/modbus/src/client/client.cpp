#include "sf/modbus/client.hpp"

#include <array>

#include <fmt/format.h>

namespace sf::modbus {

ClientError ClientError::from_exception(ExceptionCode code, std::string_view context) {
  ClientError error(Errc::remote,
                    fmt::format("{} (0x{:02X}): {}", to_string(code), static_cast<unsigned>(code), context));
  error.exception = code;
  return error;
}

namespace {

std::uint16_t max_quantity(FunctionCode function) {
  switch (function) {
    case FunctionCode::read_coils:
    case FunctionCode::read_discrete_inputs:
      return kMaxReadBits;
    case FunctionCode::write_multiple_coils:
      return kMaxWriteBits;
    case FunctionCode::write_multiple_registers:
      return kMaxWriteRegisters;
    case FunctionCode::write_single_coil:
    case FunctionCode::write_single_register:
      return 1;
    default:
      return kMaxReadRegisters;
  }
}

}  // namespace

// MB AP §6: the quantity limits of each function, checked before anything is sent.
ClientResult<Client::Reply> Client::checked(const Transaction& t) {
  const std::uint16_t max = max_quantity(t.function);
  if (t.count < 1 || t.count > max) {
    return ClientError(Errc::invalid_argument,
                       fmt::format("{}: quantity {} outside 1..{}", to_string(t.function), t.count, max));
  }
  return transact(t);
}

namespace {

// Narrows a caller's vector size to a Modbus quantity (0 = too many, refused by checked()).
std::uint16_t quantity(std::size_t n) {
  return n > 0xFFFF ? 0 : static_cast<std::uint16_t>(n);
}

// The part of a read's reply its caller asked for.
template <typename T>
ClientResult<T> take(ClientResult<Client::Reply> reply, T Client::Reply::*part) {
  if (!reply) {
    return reply.error();
  }
  return std::move((*reply).*part);
}

ClientStatus status_of(const ClientResult<Client::Reply>& reply) {
  return reply ? ClientStatus{} : ClientStatus{reply.error()};
}

}  // namespace

ClientResult<std::vector<bool>> Client::read_coils(std::uint16_t address, std::uint16_t count) {
  return take(checked({.function = FunctionCode::read_coils, .address = address, .count = count}),
              &Reply::bits);
}

ClientResult<std::vector<bool>> Client::read_discrete_inputs(std::uint16_t address, std::uint16_t count) {
  return take(checked({.function = FunctionCode::read_discrete_inputs, .address = address, .count = count}),
              &Reply::bits);
}

ClientResult<std::vector<std::uint16_t>> Client::read_holding_registers(std::uint16_t address,
                                                                        std::uint16_t count) {
  return take(checked({.function = FunctionCode::read_holding_registers, .address = address, .count = count}),
              &Reply::registers);
}

ClientResult<std::vector<std::uint16_t>> Client::read_input_registers(std::uint16_t address,
                                                                      std::uint16_t count) {
  return take(checked({.function = FunctionCode::read_input_registers, .address = address, .count = count}),
              &Reply::registers);
}

ClientStatus Client::write_single_coil(std::uint16_t address, bool value) {
  const std::vector<bool> coils{value};
  return status_of(checked(
      {.function = FunctionCode::write_single_coil, .address = address, .count = 1, .coils = &coils}));
}

ClientStatus Client::write_single_register(std::uint16_t address, std::uint16_t value) {
  const std::array<std::uint16_t, 1> values{value};
  return status_of(checked({.function = FunctionCode::write_single_register,
                            .address = address,
                            .count = 1,
                            .registers = values}));
}

ClientStatus Client::write_multiple_coils(std::uint16_t address, const std::vector<bool>& values) {
  return status_of(checked({.function = FunctionCode::write_multiple_coils,
                            .address = address,
                            .count = quantity(values.size()),
                            .coils = &values}));
}

ClientStatus Client::write_multiple_registers(std::uint16_t address, std::span<const std::uint16_t> values) {
  return status_of(checked({.function = FunctionCode::write_multiple_registers,
                            .address = address,
                            .count = quantity(values.size()),
                            .registers = values}));
}

}  // namespace sf::modbus
