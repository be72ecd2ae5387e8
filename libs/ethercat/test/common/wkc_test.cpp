// Working-counter rules of ET1100 datasheet section I ("Working Counter") for
// every command, per ESC and as the master's expectation.
#include "sf/ethercat/wkc.hpp"

#include <gtest/gtest.h>

namespace sf::ethercat {
namespace {

constexpr WkcAccess kNone{false, false};
constexpr WkcAccess kRead{true, false};
constexpr WkcAccess kWrite{false, true};
constexpr WkcAccess kBoth{true, true};

struct Rule {
  Command command;
  std::uint16_t none, read, write, both;
};

class WkcRule : public ::testing::TestWithParam<Rule> {};

TEST_P(WkcRule, IncrementPerEsc) {
  const Rule& r = GetParam();
  EXPECT_EQ(wkc_increment(r.command, kNone), r.none);
  EXPECT_EQ(wkc_increment(r.command, kRead), r.read);
  EXPECT_EQ(wkc_increment(r.command, kWrite), r.write);
  EXPECT_EQ(wkc_increment(r.command, kBoth), r.both);
}

INSTANTIATE_TEST_SUITE_P(
    Et1100SectionI, WkcRule,
    ::testing::Values(
        // Reads count only the read, writes only the write.
        Rule{Command::APRD, 0, 1, 0, 1}, Rule{Command::FPRD, 0, 1, 0, 1}, Rule{Command::BRD, 0, 1, 0, 1},
        Rule{Command::LRD, 0, 1, 0, 1}, Rule{Command::APWR, 0, 0, 1, 1}, Rule{Command::FPWR, 0, 0, 1, 1},
        Rule{Command::BWR, 0, 0, 1, 1}, Rule{Command::LWR, 0, 0, 1, 1},
        // Read-write: read +1, write +2, both +3.
        Rule{Command::APRW, 0, 1, 2, 3}, Rule{Command::FPRW, 0, 1, 2, 3}, Rule{Command::BRW, 0, 1, 2, 3},
        Rule{Command::LRW, 0, 1, 2, 3},
        // Read-multiple-write: +1 for the read at the addressed slave, +1 per write elsewhere.
        Rule{Command::ARMW, 0, 1, 1, 2}, Rule{Command::FRMW, 0, 1, 1, 2}, Rule{Command::NOP, 0, 0, 0, 0}),
    [](const auto& p) { return std::string(to_string(p.param.command)); });

TEST(ExpectedWkc, SumsWhatEachEscAdds) {
  EXPECT_EQ(expected_wkc(Command::BRD, 5, 0), 5);
  EXPECT_EQ(expected_wkc(Command::BRD, 5, 5), 5);  // the write count is irrelevant for reads
  EXPECT_EQ(expected_wkc(Command::BWR, 0, 7), 7);
  EXPECT_EQ(expected_wkc(Command::FPRD, 1, 0), 1);
  EXPECT_EQ(expected_wkc(Command::APWR, 0, 1), 1);
  // LRW over 3 slaves with inputs and 2 with outputs: 3 + 2·2.
  EXPECT_EQ(expected_wkc(Command::LRW, 3, 2), 7);
  EXPECT_EQ(expected_wkc(Command::LRD, 3, 2), 3);
  EXPECT_EQ(expected_wkc(Command::LWR, 3, 2), 2);
  EXPECT_EQ(expected_wkc(Command::APRW, 1, 1), 3);
  // FRMW distributing the reference clock over n = 4 slaves: 1 read + 3 writes.
  EXPECT_EQ(expected_wkc(Command::FRMW, 1, 3), 4);
  EXPECT_EQ(expected_wkc(Command::ARMW, 1, 3), 4);
  EXPECT_EQ(expected_wkc(Command::NOP, 9, 9), 0);
}

TEST(ExpectedWkc, MatchesTheSumOfPerEscIncrements) {
  // A segment of 6 ESCs where ESC i reads if i is even and writes if i % 3 == 0.
  for (std::uint8_t c = 0; c <= 14; ++c) {
    const auto cmd = static_cast<Command>(c);
    std::uint16_t sum = 0;
    std::size_t readers = 0;
    std::size_t writers = 0;
    for (int i = 0; i < 6; ++i) {
      const WkcAccess a{i % 2 == 0, i % 3 == 0};
      sum = static_cast<std::uint16_t>(sum + wkc_increment(cmd, a));
      readers += a.read ? 1U : 0U;
      writers += a.write ? 1U : 0U;
    }
    EXPECT_EQ(expected_wkc(cmd, readers, writers), sum) << to_string(cmd);
  }
}

TEST(ExpectedWkc, WrapsLikeThe16BitField) {
  EXPECT_EQ(expected_wkc(Command::LRW, 0, 0x8001), 2);
}

}  // namespace
}  // namespace sf::ethercat
