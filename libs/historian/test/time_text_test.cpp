#include <gtest/gtest.h>

#include "sf/historian/time_text.hpp"

namespace sf::historian {
namespace {

using namespace std::chrono_literals;

const Timestamp kNow = from_micros(1'763'720'130'250'000);  // 2025-11-21T10:15:30.25Z

TEST(ParseDuration, UnitsAndCombinations) {
  EXPECT_EQ(parse_duration("500ms").value_or(0us), 500ms);
  EXPECT_EQ(parse_duration("1s").value_or(0us), 1s);
  EXPECT_EQ(parse_duration("10m").value_or(0us), 10min);
  EXPECT_EQ(parse_duration("7d").value_or(0us), 168h);
  EXPECT_EQ(parse_duration("1w").value_or(0us), 168h);
  EXPECT_EQ(parse_duration("1h30m").value_or(0us), 90min);
  EXPECT_EQ(parse_duration("250us").value_or(0us), 250us);
  for (const char* bad : {"", "10", "ms", "1x", "-1s", "99999999999999999999d", "9999999999999w"}) {
    EXPECT_FALSE(parse_duration(bad).ok()) << bad;
  }
}

TEST(ParseTime, RelativeAndNow) {
  EXPECT_EQ(parse_time("now", kNow).value_or(Timestamp{}), kNow);
  EXPECT_EQ(parse_time("-10m", kNow).value_or(Timestamp{}), kNow - 10min);
  EXPECT_EQ(parse_time("now-1h", kNow).value_or(Timestamp{}), kNow - 1h);
  EXPECT_EQ(parse_time("+1d", kNow).value_or(Timestamp{}), kNow + 24h);
}

TEST(ParseTime, Iso8601) {
  EXPECT_EQ(parse_time("2025-11-21T10:15:30.25Z", {}).value_or(Timestamp{}), kNow);
  EXPECT_EQ(parse_time("2025-11-21T11:15:30.250+01:00", {}).value_or(Timestamp{}), kNow);
  EXPECT_EQ(parse_time("2025-11-21 05:15:30.25-0500", {}).value_or(Timestamp{}), kNow);
  EXPECT_EQ(parse_time("2025-11-21T10:15:30.25", {}).value_or(Timestamp{}), kNow);  // UTC when no zone
  EXPECT_EQ(parse_time("2025-11-21", {}).value_or(Timestamp{}), kNow - 10h - 15min - 30s - 250ms);
  EXPECT_EQ(parse_time("2025-11-21T10:15Z", {}).value_or(Timestamp{}), kNow - 30s - 250ms);
  for (const char* bad : {"2025-13-01", "2025-02-30", "2025-11-21T25:00", "2025-11-21T10", "21.11.2025",
                          "2025-11-21T10:15:30Q", "yesterday", "-10"}) {
    auto t = parse_time(bad, kNow);
    ASSERT_FALSE(t.ok()) << bad;
    EXPECT_EQ(t.error().code, Errc::invalid_argument);
  }
}

TEST(FormatTime, Iso8601Utc) {
  EXPECT_EQ(format_time(kNow), "2025-11-21T10:15:30.250000Z");
  EXPECT_EQ(format_time(kNow - 250ms), "2025-11-21T10:15:30Z");
  EXPECT_EQ(format_time(from_micros(-1)), "1969-12-31T23:59:59.999999Z");
  EXPECT_EQ(parse_time(format_time(kNow), {}).value_or(Timestamp{}), kNow);
}

}  // namespace
}  // namespace sf::historian
