// Contract Net negotiation latency and rate (paper §IV.B), contractors in
// this process, over DDS on loopback: 1, 4, 16 and 64 contractors, each row
// next to Cyclone's ddsperf ping/pong round trip at the same fan-out (one pong
// process per contractor) measured in the same run, and the CPU time of all
// processes per negotiation next to ddsperf's per round trip. "ddsperf p50" is
// a lower bound of the median round trip to all pongs, "ddsperf mean" ping's
// cycle (sf::negotiation::FanOutRoundTrip). The same
// figures with each contractor in its own process: bench/bench_cnp.sh.
//
// Latency is ANNOUNCE → confirmed AWARD (two DDS round trips: ANNOUNCE/BID,
// AWARD/CONFIRM, plus every contractor's bid), one negotiation at a time.
// "in flight" is the rate with 8 negotiations under way at once.
//
// Usage: bench_cnp [NEGOTIATIONS]   (default 500 per phase)
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <optional>
#include <string>

#include "sf/bench/cnp.hpp"

namespace cnp = sf::negotiation;

namespace {

double or_nan(const std::optional<double>& v) {
  return v.value_or(std::numeric_limits<double>::quiet_NaN());
}

}  // namespace

int main(int argc, char** argv) {
  const std::size_t negotiations = argc > 1 ? std::strtoul(argv[1], nullptr, 10) : 500;
  cnp::BenchOptions base;
  base.negotiations = negotiations == 0 ? 500 : negotiations;
  std::printf("%11s %9s %9s %9s %15s %13s %11s %8s %12s %10s %11s %9s\n", "contractors", "p50 us", "p99 us",
              "mean us", "one-at-a-time/s", "8-in-flight/s", "ddsperf p50", "ratio", "ddsperf mean",
              "mean ratio", "CPU us/neg", "CPU ratio");
  for (std::size_t n : {1U, 4U, 16U, 64U}) {
    auto options = base;
    options.contractors = n;
    auto r = cnp::run_bench(options);
    if (!r) {
      std::printf("%11zu failed: %s\n", n, r.error().describe().c_str());
      continue;
    }
    std::printf("%11zu %9.1f %9.1f %9.1f %15.0f %13.0f %11.1f %7.2fx %12.1f %9.2fx %11.1f %8.2fx\n", n,
                r->latency.p50_us, r->latency.p99_us, r->latency.mean_us, r->sequential_per_s,
                r->pipelined_per_s, or_nan(r->ddsperf_rtt_p50_us), or_nan(r->ratio_p50),
                or_nan(r->ddsperf_rtt_mean_us), or_nan(r->ratio_mean), or_nan(r->cpu_us_per_negotiation),
                or_nan(r->cpu_ratio));
  }
  return 0;
}
