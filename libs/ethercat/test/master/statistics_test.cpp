#include "sf/ethercat/master/statistics.hpp"

#include <gtest/gtest.h>

namespace sf::ethercat::master {
namespace {

using std::chrono::nanoseconds;

TEST(DurationHistogram, EmptyReportsZero) {
  DurationHistogram h;
  EXPECT_EQ(h.count(), 0U);
  EXPECT_EQ(h.min(), nanoseconds{0});
  EXPECT_EQ(h.max(), nanoseconds{0});
  EXPECT_EQ(h.median(), nanoseconds{0});
}

TEST(DurationHistogram, SmallValuesAreExact) {
  DurationHistogram h;
  for (int v = 0; v < 16; ++v) {
    h.record(nanoseconds{v});
  }
  EXPECT_EQ(h.min(), nanoseconds{0});
  EXPECT_EQ(h.max(), nanoseconds{15});
  EXPECT_EQ(h.quantile(0.5), nanoseconds{7});
  EXPECT_EQ(h.quantile(1.0), nanoseconds{15});
}

TEST(DurationHistogram, QuantilesWithinOneSixteenth) {
  DurationHistogram h;
  // 1..100 µs, uniformly.
  for (int us = 1; us <= 100; ++us) {
    h.record(nanoseconds{us * 1000});
  }
  const auto within = [](nanoseconds got, double want) {
    const auto g = static_cast<double>(got.count());
    return g >= want && g <= want * (1.0 + 1.0 / 16.0);
  };
  EXPECT_TRUE(within(h.median(), 50'000)) << h.median().count();
  EXPECT_TRUE(within(h.quantile(0.99), 99'000)) << h.quantile(0.99).count();
  EXPECT_EQ(h.max(), nanoseconds{100'000});
  EXPECT_EQ(h.min(), nanoseconds{1'000});
}

TEST(DurationHistogram, HugeAndNegativeValuesAreClamped) {
  DurationHistogram h;
  h.record(nanoseconds{-5});
  h.record(nanoseconds{std::int64_t{1} << 50});
  EXPECT_EQ(h.count(), 2U);
  EXPECT_EQ(h.min(), nanoseconds{0});
  EXPECT_EQ(h.quantile(1.0), nanoseconds{std::int64_t{1} << 50});
}

TEST(CycleStatistics, SummaryNamesTheCounters) {
  CycleStatistics s;
  s.cycles = 10;
  s.lost_frames = 2;
  s.round_trip.record(nanoseconds{12'000});
  const auto text = s.summary();
  EXPECT_NE(text.find("cycles 10"), std::string::npos) << text;
  EXPECT_NE(text.find("lost 2"), std::string::npos) << text;
  EXPECT_NE(text.find("12.0"), std::string::npos) << text;
}

}  // namespace
}  // namespace sf::ethercat::master
