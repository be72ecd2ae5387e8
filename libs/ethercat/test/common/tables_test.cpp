// The generated spec tables (tables/*.csv → sf/ethercat/*_codes.hpp).
#include <set>

#include <gtest/gtest.h>

#include "sf/ethercat/al_status_codes.hpp"
#include "sf/ethercat/sdo_abort_codes.hpp"

namespace sf::ethercat {
namespace {

TEST(AlStatusCodes, DescribeFromEtg1000_6Table11) {
  EXPECT_EQ(describe(AlStatusCode::NoError), "No error");
  EXPECT_EQ(describe(AlStatusCode::InvalidRequestedStateChange), "Invalid requested state change");
  EXPECT_EQ(static_cast<std::uint16_t>(AlStatusCode::InvalidRequestedStateChange), 0x0011);
  EXPECT_EQ(describe(static_cast<AlStatusCode>(0x001B)), "Sync manager watchdog");
  EXPECT_EQ(describe(static_cast<AlStatusCode>(0x001D)), "Invalid output configuration");
  EXPECT_EQ(name_of(AlStatusCode::SyncManagerWatchdog), "SyncManagerWatchdog");
  EXPECT_EQ(describe(static_cast<AlStatusCode>(0x7777)), "unknown AL status code");
  EXPECT_FALSE(is_known(static_cast<AlStatusCode>(0x7777)));
}

TEST(SdoAbortCodes, DescribeFromEtg1000_6AndCia301) {
  EXPECT_EQ(describe(SdoAbortCode::ObjectDoesNotExist), "Object does not exist in the object dictionary");
  EXPECT_EQ(static_cast<std::uint32_t>(SdoAbortCode::ObjectDoesNotExist), 0x06020000U);
  EXPECT_EQ(describe(static_cast<SdoAbortCode>(0x05030000)), "Toggle bit not changed");
  EXPECT_EQ(describe(static_cast<SdoAbortCode>(0x06090011)), "Subindex does not exist");
  EXPECT_EQ(describe(static_cast<SdoAbortCode>(0x12345678)), "unknown SDO abort code");
}

TEST(GeneratedTables, ValuesAreUniqueSortedAndDescribed) {
  std::set<std::uint32_t> seen;
  std::uint32_t last = 0;
  for (const auto c : kAllSdoAbortCodes) {
    const auto v = static_cast<std::uint32_t>(c);
    EXPECT_TRUE(seen.insert(v).second);
    EXPECT_GE(v, last);
    last = v;
    EXPECT_TRUE(is_known(c));
    EXPECT_NE(describe(c), "unknown SDO abort code");
  }
  EXPECT_GE(kAllSdoAbortCodes.size(), 30U);
  EXPECT_GE(kAllAlStatusCodes.size(), 50U);
  for (const auto c : kAllAlStatusCodes) {
    EXPECT_TRUE(is_known(c));
  }
}

}  // namespace
}  // namespace sf::ethercat
