// RegisterBank: the four Modbus tables of one device (MB AP §4.3), each with its own start
// address and size. It owns a libmodbus modbus_mapping_t (modbus_mapping_new_start_address), so
// libmodbus's modbus_reply serves it as it is, and gives typed access to each table.
//
// Addresses are absolute Modbus addresses: a table laid out as {start 100, count 10} holds
// addresses 100..109. A bank is not thread-safe: the Device that serves it says who may touch
// it when (device.hpp).
#pragma once

#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "sf/core/result.hpp"
#include "sf/modbus/protocol.hpp"

// libmodbus's mapping type (modbus.h), declared here so its macros stay out of this header.
struct _modbus_mapping_t;  // NOLINT(bugprone-reserved-identifier)

namespace sf::modbus {

struct TableLayout {
  std::uint16_t start = 0;
  std::uint16_t count = 0;

  friend bool operator==(const TableLayout&, const TableLayout&) = default;
};

struct BankLayout {
  TableLayout coils{};
  TableLayout discrete_inputs{};
  TableLayout holding_registers{};
  TableLayout input_registers{};

  [[nodiscard]] const TableLayout& operator[](Table table) const;
  friend bool operator==(const BankLayout&, const BankLayout&) = default;
};

class RegisterBank {
 public:
  // Every table must end at or below address 0xFFFF (start + count <= 0x10000);
  // Errc::invalid_argument names the table that does not.
  static Result<RegisterBank> create(const BankLayout& layout);

  RegisterBank(RegisterBank&&) noexcept = default;
  RegisterBank& operator=(RegisterBank&&) noexcept = default;
  ~RegisterBank();

  [[nodiscard]] const BankLayout& layout() const { return layout_; }
  // True when address..address+count-1 all lie in the table.
  [[nodiscard]] bool contains(Table table, std::uint32_t address, std::uint32_t count = 1) const;

  // One entry each. The address must lie in the table (contains()): a programming error
  // otherwise, caught by an assertion; release builds read 0 / false and ignore the write.
  [[nodiscard]] bool coil(std::uint16_t address) const { return bit(Table::coils, address); }
  void set_coil(std::uint16_t address, bool value) { set_bit(Table::coils, address, value); }
  [[nodiscard]] bool discrete_input(std::uint16_t address) const {
    return bit(Table::discrete_inputs, address);
  }
  void set_discrete_input(std::uint16_t address, bool value) {
    set_bit(Table::discrete_inputs, address, value);
  }
  [[nodiscard]] std::uint16_t holding_register(std::uint16_t address) const {
    return word(Table::holding_registers, address);
  }
  void set_holding_register(std::uint16_t address, std::uint16_t value) {
    set_word(Table::holding_registers, address, value);
  }
  [[nodiscard]] std::uint16_t input_register(std::uint16_t address) const {
    return word(Table::input_registers, address);
  }
  void set_input_register(std::uint16_t address, std::uint16_t value) {
    set_word(Table::input_registers, address, value);
  }

  // The same by table (coils and discrete inputs are bit tables, the others register tables).
  [[nodiscard]] bool bit(Table table, std::uint16_t address) const;
  void set_bit(Table table, std::uint16_t address, bool value);
  [[nodiscard]] std::uint16_t word(Table table, std::uint16_t address) const;
  void set_word(Table table, std::uint16_t address, std::uint16_t value);

  // Runs of entries; the range must lie in the table, as above.
  [[nodiscard]] std::vector<bool> bits(Table table, std::uint16_t address, std::uint16_t count) const;
  void set_bits(Table table, std::uint16_t address, const std::vector<bool>& values);
  [[nodiscard]] std::vector<std::uint16_t> words(Table table, std::uint16_t address,
                                                 std::uint16_t count) const;
  void set_words(Table table, std::uint16_t address, std::span<const std::uint16_t> values);

  // The libmodbus mapping behind the tables, for modbus_reply.
  [[nodiscard]] _modbus_mapping_t* mapping() { return mapping_.get(); }

 private:
  struct MappingFree {
    void operator()(_modbus_mapping_t* mapping) const;
  };

  RegisterBank(const BankLayout& layout, _modbus_mapping_t* mapping);
  [[nodiscard]] std::uint8_t* bit_table(Table table) const;
  [[nodiscard]] std::uint16_t* word_table(Table table) const;

  BankLayout layout_;
  std::unique_ptr<_modbus_mapping_t, MappingFree> mapping_;
};

}  // namespace sf::modbus
