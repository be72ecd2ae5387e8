#include "sf/line/registers.hpp"

#include <cstdlib>
#include <fstream>
#include <set>
#include <sstream>
#include <string>

#include <gtest/gtest.h>

namespace sf::line {
namespace {

void expect_fits(std::span<const RegisterEntry> map, const modbus::BankLayout& layout) {
  std::set<std::pair<modbus::Table, std::uint16_t>> seen;
  for (const auto& e : map) {
    EXPECT_TRUE(seen.insert({e.table, e.address}).second) << e.name << " shares its address";
    const auto& table = layout[e.table];
    EXPECT_GE(e.address, table.start) << e.name;
    EXPECT_LT(e.address, table.start + table.count) << e.name << " is outside its bank";
    if (e.address == kRepeatBase) {
      EXPECT_LE(kRepeatBase + kMaxRepeats, table.start + table.count) << e.name << "[k] does not fit";
    }
  }
}

TEST(RegistersTest, EveryEntryHasItsOwnAddressInsideItsBank) {
  expect_fits(conveyor_plc::map(), conveyor_bank_layout());
  expect_fits(transfer_plc::map(), transfer_bank_layout());
  expect_fits(robot_controller::map(), robot_bank_layout());
}

// docs/plant.md shows the maps as `smartfactory plant registers` prints them.
TEST(RegistersTest, TheDocsShowTheseMaps) {
  const char* root = std::getenv("SF_SOURCE_DIR");
  ASSERT_NE(root, nullptr);
  std::ifstream in(std::string(root) + "/docs/plant.md");
  ASSERT_TRUE(in);
  std::stringstream text;
  text << in.rdbuf();
  for (auto map : {conveyor_plc::map(), transfer_plc::map(), robot_controller::map()}) {
    EXPECT_NE(text.str().find(markdown(map)), std::string::npos) << "docs/plant.md lacks\n" << markdown(map);
  }
}

}  // namespace
}  // namespace sf::line
