// The benchmark's reading of ddsperf's output at a fan-out: round trips to all pongs from the
// slowest pong of each second and from the pings every pong answered.
#include <gtest/gtest.h>

#include <cstdint>
#include <cstdio>
#include <ctime>
#include <fstream>

#include <unistd.h>

#include <fmt/format.h>

#include "sf/bench/cnp.hpp"

namespace sf::negotiation {
namespace {

// One per-pong line of ddsperf ping's output.
std::string pong_line(std::string_view time, std::string_view pong, double median, int answers) {
  return fmt::format(
      "[101] {}  vm:{} size 12 mean 9.0us min 3.0us 50% {}us 90% 9.0us 99% 10.0us max 40us cnt {}\n", time,
      pong, median, answers);
}

std::string write_temp(const std::string& text) {
  char name[] = "/tmp/sf-ddsperf-XXXXXX";
  const int fd = ::mkstemp(name);
  ::close(fd);
  std::ofstream(name) << text;
  return name;
}

// ddsperf prints half round trips (FanOutRoundTrip): a round trip is twice the printed figure.
TEST(DdsperfOutput, TheSlowestPongOfEachSecondGivesTwiceItsMedianAsTheFanOutRoundTrip) {
  const std::string path =
      write_temp("[101] participant vm:102: new\n" + pong_line("1.000", "102", 8.0, 100) +
                 pong_line("1.000", "103", 12.0, 100) +
                 "[101] 1.000  rss:8.9MB vcsw:33852 ivcsw:12673 ddsperf:1%+0% recvMC:0%+11% recvUC:7%+37%\n" +
                 pong_line("2.000", "102", 7.0, 100) + pong_line("2.000", "103", 20.0, 100) +
                 pong_line("3.000", "102", 30.0, 200) + pong_line("3.000", "103", 5.0, 200));
  const auto rt = parse_ddsperf_output(path);
  std::remove(path.c_str());
  ASSERT_TRUE(rt.has_value());
  // Per second the slowest median: 12, 20, 30; their median 20 is half a round trip.
  EXPECT_DOUBLE_EQ(rt->p50_us, 40.0);
  EXPECT_EQ(rt->pings, 400U);
}

// ping waits for every pong before the next ping: the pings every pong answered per second give
// the mean fan-out round trip. The first report's interval starts before the first ping.
TEST(DdsperfOutput, TheMeanRoundTripIsOnePingCycle) {
  const std::string path =
      write_temp(pong_line("1.000", "102", 8.0, 7) + pong_line("1.000", "103", 8.0, 7) +
                 pong_line("2.000", "102", 8.0, 20001) + pong_line("2.000", "103", 8.0, 20000) +
                 pong_line("3.000", "102", 8.0, 30000) +
                 // vm:103 answered nothing in the fourth second, so no ping completed.
                 pong_line("4.000", "102", 8.0, 5) + pong_line("5.000", "102", 8.0, 20000) +
                 pong_line("5.000", "103", 8.0, 20000));
  const auto rt = parse_ddsperf_output(path);
  std::remove(path.c_str());
  ASSERT_TRUE(rt.has_value());
  // Seconds 2 to 5: 20000 + 0 + 0 + 20000 pings in 4 s.
  ASSERT_TRUE(rt->mean_us.has_value());
  EXPECT_DOUBLE_EQ(*rt->mean_us, 4e6 / 40000);
  EXPECT_EQ(rt->pings, 40007U);
}

TEST(DdsperfOutput, OneReportHasNoMeanCycle) {
  const std::string path = write_temp(pong_line("1.000", "102", 8.0, 7));
  const auto rt = parse_ddsperf_output(path);
  std::remove(path.c_str());
  ASSERT_TRUE(rt.has_value());
  EXPECT_FALSE(rt->mean_us.has_value());
  EXPECT_DOUBLE_EQ(rt->p50_us, 16.0);
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
