// Request: what a Modbus request asks of a device, decoded from its PDU (MB AP §6). Device hooks
// see it before the request is answered and after a write was applied.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <string>

#include "sf/modbus/protocol.hpp"

namespace sf::modbus {

// A run of `count` entries of one table from `address` (absolute Modbus addresses, 0-based as on
// the wire).
struct Range {
  Table table = Table::coils;
  std::uint16_t address = 0;
  std::uint16_t count = 0;

  friend bool operator==(const Range&, const Range&) = default;
};

struct Request {
  std::uint8_t unit_id = kTcpUnitId;
  FunctionCode function = FunctionCode::read_coils;
  // The entries the response reports (reads, and the read part of read_write_multiple_registers).
  std::optional<Range> read;
  // The entries the request changes (writes, and the write part of read_write_multiple_registers).
  std::optional<Range> write;
  // The values to write as they are on the wire (big-endian registers, coils packed LSB first;
  // write_single_coil: 0xFF00 or 0x0000; mask_write_register: AND mask, OR mask). Valid only
  // while the hook that receives the request runs.
  std::span<const std::uint8_t> data;

  [[nodiscard]] bool writes() const { return write.has_value(); }
  // Written value i: register i of data, or coil i (write_single_coil: data == 0xFF00).
  [[nodiscard]] std::uint16_t register_value(std::size_t i) const;
  [[nodiscard]] bool coil_value(std::size_t i) const;
  // "read_holding_registers 40..49 (unit 255)".
  [[nodiscard]] std::string describe() const;
};

}  // namespace sf::modbus
