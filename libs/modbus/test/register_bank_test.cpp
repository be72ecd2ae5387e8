#include "sf/modbus/register_bank.hpp"

#include <modbus.h>

#include <gtest/gtest.h>

#include "test_support.hpp"

namespace sf::modbus::test {
namespace {

TEST(RegisterBank, TypedAccessUsesAbsoluteAddresses) {
  RegisterBank bank = make_bank();
  bank.set_coil(31, true);
  bank.set_discrete_input(115, true);
  bank.set_holding_register(1000, 0xBEEF);
  bank.set_input_register(2019, 7);

  EXPECT_TRUE(bank.coil(31));
  EXPECT_FALSE(bank.coil(30));
  EXPECT_TRUE(bank.discrete_input(115));
  EXPECT_EQ(bank.holding_register(1000), 0xBEEF);
  EXPECT_EQ(bank.input_register(2019), 7);
}

TEST(RegisterBank, MappingIsWhatLibmodbusServes) {
  RegisterBank bank = make_bank();
  bank.set_coil(3, true);
  bank.set_discrete_input(101, true);
  bank.set_holding_register(1010, 42);
  bank.set_input_register(2005, 43);

  const modbus_mapping_t* m = bank.mapping();
  EXPECT_EQ(m->start_bits, 0);
  EXPECT_EQ(m->nb_bits, 32);
  EXPECT_EQ(m->start_input_bits, 100);
  EXPECT_EQ(m->nb_input_bits, 16);
  EXPECT_EQ(m->start_registers, 1000);
  EXPECT_EQ(m->nb_registers, 100);
  EXPECT_EQ(m->start_input_registers, 2000);
  EXPECT_EQ(m->nb_input_registers, 20);
  EXPECT_EQ(m->tab_bits[3], 1);
  EXPECT_EQ(m->tab_input_bits[1], 1);
  EXPECT_EQ(m->tab_registers[10], 42);
  EXPECT_EQ(m->tab_input_registers[5], 43);
}

TEST(RegisterBank, RangesReadAndWriteRuns) {
  RegisterBank bank = make_bank();
  const std::vector<std::uint16_t> values{1, 2, 3};
  bank.set_words(Table::holding_registers, 1097, values);
  bank.set_bits(Table::coils, 29, {true, false, true});

  EXPECT_EQ(bank.words(Table::holding_registers, 1097, 3), values);
  EXPECT_EQ(bank.bits(Table::coils, 29, 3), (std::vector<bool>{true, false, true}));
}

TEST(RegisterBank, ContainsChecksEveryEntryOfARange) {
  RegisterBank bank = make_bank();
  EXPECT_TRUE(bank.contains(Table::holding_registers, 1000, 100));
  EXPECT_FALSE(bank.contains(Table::holding_registers, 999, 1));
  EXPECT_FALSE(bank.contains(Table::holding_registers, 1001, 100));
  EXPECT_FALSE(bank.contains(Table::input_registers, 0xFFFF, 2));
  EXPECT_TRUE(bank.contains(Table::coils, 0, 0));
}

TEST(RegisterBank, EmptyTablesHoldNothing) {
  auto bank = RegisterBank::create(BankLayout{.holding_registers = {10, 2}});
  ASSERT_TRUE(bank.ok());
  EXPECT_FALSE(bank->contains(Table::coils, 0));
  EXPECT_FALSE(bank->contains(Table::input_registers, 0));
  EXPECT_TRUE(bank->contains(Table::holding_registers, 11));
}

TEST(RegisterBank, RefusesATablePastTheAddressSpace) {
  auto bank = RegisterBank::create(BankLayout{.input_registers = {0xFFF0, 0x20}});
  ASSERT_FALSE(bank.ok());
  EXPECT_EQ(bank.error().code, Errc::invalid_argument);
  EXPECT_NE(bank.error().message.find("input_registers"), std::string::npos);

  EXPECT_TRUE(RegisterBank::create(BankLayout{.coils = {0xFFF0, 0x10}}).ok());
}

TEST(RegisterBank, MovesKeepTheMapping) {
  RegisterBank a = make_bank();
  a.set_holding_register(1050, 9);
  modbus_mapping_t* mapping = a.mapping();
  RegisterBank b = std::move(a);
  EXPECT_EQ(b.mapping(), mapping);
  EXPECT_EQ(b.holding_register(1050), 9);
}

}  // namespace
}  // namespace sf::modbus::test
