#include "sf/modbus/request.hpp"

#include <fmt/format.h>

#include "wire.hpp"

namespace sf::modbus {

std::uint16_t Request::register_value(std::size_t i) const {
  if (2 * i + 2 > data.size()) {
    return 0;
  }
  return wire::load_be16(&data[2 * i]);
}

bool Request::coil_value(std::size_t i) const {
  if (function == FunctionCode::write_single_coil) {
    return i == 0 && register_value(0) == wire::kCoilOn;
  }
  if (i / 8 >= data.size()) {
    return false;
  }
  return ((static_cast<unsigned>(data[i / 8]) >> (i % 8)) & 1U) != 0;
}

namespace {

std::string range_text(const Range& range) {
  if (range.count <= 1) {
    return fmt::format("{} {}", to_string(range.table), range.address);
  }
  return fmt::format("{} {}..{}", to_string(range.table), range.address, range.address + range.count - 1);
}

}  // namespace

std::string Request::describe() const {
  std::string out = function_name(static_cast<std::uint8_t>(function));
  if (read) {
    out += " read " + range_text(*read);
  }
  if (write) {
    out += " write " + range_text(*write);
  }
  out += fmt::format(" (unit {})", unit_id);
  return out;
}

}  // namespace sf::modbus
