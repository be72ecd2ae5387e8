#include "sf/modbus/register_bank.hpp"

#include <modbus.h>

#include <cassert>
#include <cerrno>

#include <fmt/format.h>

namespace sf::modbus {

const TableLayout& BankLayout::operator[](Table table) const {
  switch (table) {
    case Table::coils:
      return coils;
    case Table::discrete_inputs:
      return discrete_inputs;
    case Table::holding_registers:
      return holding_registers;
    case Table::input_registers:
      break;
  }
  return input_registers;
}

void RegisterBank::MappingFree::operator()(_modbus_mapping_t* mapping) const {
  modbus_mapping_free(mapping);
}

Result<RegisterBank> RegisterBank::create(const BankLayout& layout) {
  constexpr std::uint32_t kAddressSpace = 0x10000;
  for (Table table :
       {Table::coils, Table::discrete_inputs, Table::holding_registers, Table::input_registers}) {
    const TableLayout& t = layout[table];
    if (std::uint32_t{t.start} + t.count > kAddressSpace) {
      return make_error(Errc::invalid_argument,
                        fmt::format("{} {}+{} end past address 0xFFFF", to_string(table), t.start, t.count));
    }
  }
  modbus_mapping_t* mapping = modbus_mapping_new_start_address(
      layout.coils.start, layout.coils.count, layout.discrete_inputs.start, layout.discrete_inputs.count,
      layout.holding_registers.start, layout.holding_registers.count, layout.input_registers.start,
      layout.input_registers.count);
  if (mapping == nullptr) {
    return make_error(Errc::io, fmt::format("modbus_mapping_new_start_address: {}", modbus_strerror(errno)));
  }
  return RegisterBank(layout, mapping);
}

RegisterBank::RegisterBank(const BankLayout& layout, _modbus_mapping_t* mapping)
    : layout_(layout), mapping_(mapping) {}

RegisterBank::~RegisterBank() = default;

bool RegisterBank::contains(Table table, std::uint32_t address, std::uint32_t count) const {
  const TableLayout& t = layout_[table];
  return address >= t.start && address + count <= std::uint32_t{t.start} + t.count;
}

std::uint8_t* RegisterBank::bit_table(Table table) const {
  return table == Table::coils ? mapping_->tab_bits : mapping_->tab_input_bits;
}

std::uint16_t* RegisterBank::word_table(Table table) const {
  return table == Table::holding_registers ? mapping_->tab_registers : mapping_->tab_input_registers;
}

bool RegisterBank::bit(Table table, std::uint16_t address) const {
  assert(table == Table::coils || table == Table::discrete_inputs);
  assert(contains(table, address));
  if (!contains(table, address)) {
    return false;
  }
  return bit_table(table)[address - layout_[table].start] != 0;
}

void RegisterBank::set_bit(Table table, std::uint16_t address, bool value) {
  assert(table == Table::coils || table == Table::discrete_inputs);
  assert(contains(table, address));
  if (contains(table, address)) {
    bit_table(table)[address - layout_[table].start] = value ? 1 : 0;
  }
}

std::uint16_t RegisterBank::word(Table table, std::uint16_t address) const {
  assert(table == Table::holding_registers || table == Table::input_registers);
  assert(contains(table, address));
  if (!contains(table, address)) {
    return 0;
  }
  return word_table(table)[address - layout_[table].start];
}

void RegisterBank::set_word(Table table, std::uint16_t address, std::uint16_t value) {
  assert(table == Table::holding_registers || table == Table::input_registers);
  assert(contains(table, address));
  if (contains(table, address)) {
    word_table(table)[address - layout_[table].start] = value;
  }
}

std::vector<bool> RegisterBank::bits(Table table, std::uint16_t address, std::uint16_t count) const {
  std::vector<bool> out(count);
  for (std::uint16_t i = 0; i < count; ++i) {
    out[i] = bit(table, static_cast<std::uint16_t>(address + i));
  }
  return out;
}

void RegisterBank::set_bits(Table table, std::uint16_t address, const std::vector<bool>& values) {
  for (std::size_t i = 0; i < values.size(); ++i) {
    set_bit(table, static_cast<std::uint16_t>(address + i), values[i]);
  }
}

std::vector<std::uint16_t> RegisterBank::words(Table table, std::uint16_t address,
                                               std::uint16_t count) const {
  std::vector<std::uint16_t> out(count);
  for (std::uint16_t i = 0; i < count; ++i) {
    out[i] = word(table, static_cast<std::uint16_t>(address + i));
  }
  return out;
}

void RegisterBank::set_words(Table table, std::uint16_t address, std::span<const std::uint16_t> values) {
  for (std::size_t i = 0; i < values.size(); ++i) {
    set_word(table, static_cast<std::uint16_t>(address + i), values[i]);
  }
}

}  // namespace sf::modbus
