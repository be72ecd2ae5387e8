// The benchmark's reading of ddsperf's output at a fan-out: the slowest pong of each second is
// that second's round trip to all pongs.
#include <gtest/gtest.h>

#include <cstdint>
#include <cstdio>
#include <ctime>
#include <fstream>

#include <unistd.h>

#include "sf/negotiation/bench.hpp"

namespace sf::negotiation {
namespace {

std::string write_temp(const std::string& text) {
  char name[] = "/tmp/sf-ddsperf-XXXXXX";
  const int fd = ::mkstemp(name);
  ::close(fd);
  std::ofstream(name) << text;
  return name;
}

TEST(DdsperfOutput, TheSlowestPongOfEachSecondIsTheFanOutRoundTrip) {
  const std::string path = write_temp(
      "[101] participant vm:102: new\n"
      "[101] 1.000  vm:102 size 12 mean 9.0us min 3.0us 50% 8.0us 90% 9.0us 99% 10.0us max 40us cnt 100\n"
      "[101] 1.000  vm:103 size 12 mean 11.0us min 4.0us 50% 12.0us 90% 13.0us 99% 14.0us max 50us cnt 100\n"
      "[101] 2.000  vm:102 size 12 mean 9.0us min 3.0us 50% 7.0us 90% 9.0us 99% 10.0us max 40us cnt 100\n"
      "[101] 2.000  vm:103 size 12 mean 9.0us min 3.0us 50% 20.0us 90% 9.0us 99% 10.0us max 40us cnt 100\n"
      "[101] 3.000  vm:102 size 12 mean 10.0us min 3.0us 50% 30.0us 90% 9.0us 99% 10.0us max 40us cnt 200\n");
  const auto stats = parse_ddsperf_output(path);
  std::remove(path.c_str());
  ASSERT_TRUE(stats.has_value());
  // Per second: max(8, 12) = 12, max(7, 20) = 20, 30; their median is 20.
  EXPECT_DOUBLE_EQ(stats->p50_us, 20.0);
  EXPECT_EQ(stats->samples, 600U);
  EXPECT_DOUBLE_EQ(stats->mean_us, (9.0 * 100 + 11.0 * 100 + 9.0 * 100 + 9.0 * 100 + 10.0 * 200) / 600);
}

TEST(DdsperfOutput, NoRoundTripLinesIsNothing) {
  const std::string path = write_temp("[101] participant vm:102: new\nterminated\n");
  EXPECT_FALSE(parse_ddsperf_output(path).has_value());
  std::remove(path.c_str());
  EXPECT_FALSE(parse_ddsperf_output("/nonexistent/ddsperf.out").has_value());
}

TEST(ProcessCpuTime, GrowsWithWorkAndIsNothingForAProcessThatIsGone) {
  const auto before = process_cpu_time(::getpid());
  ASSERT_TRUE(before.has_value());
  // Work until this process's clock says 20 ms of CPU were used.
  volatile std::uint64_t sink = 0;
  const auto start = std::clock();
  while (std::clock() - start < CLOCKS_PER_SEC / 50) {
    sink = sink + 1;
  }
  const auto after = process_cpu_time(::getpid());
  ASSERT_TRUE(after.has_value());
  EXPECT_GT(*after - *before, std::chrono::milliseconds{10});
  EXPECT_FALSE(process_cpu_time(-1).has_value());
}

}  // namespace
}  // namespace sf::negotiation
