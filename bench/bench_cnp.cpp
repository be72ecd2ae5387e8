// Contract Net negotiation latency and rate (paper §IV.B), contractors in
// this process, over DDS on loopback: 1, 4, 16 and 64 contractors, next to
// Cyclone's ddsperf ping/pong round trip measured in the same run. The same
// figures with each contractor in its own process: bench/bench_cnp.sh.
//
// Latency is ANNOUNCE → confirmed AWARD (two DDS round trips: ANNOUNCE/BID,
// AWARD/CONFIRM, plus every contractor's bid), one negotiation at a time.
// "in flight" is the rate with 8 negotiations under way at once.
//
// Usage: bench_cnp [NEGOTIATIONS]   (default 500 per phase)
#include <cstdio>
#include <cstdlib>
#include <string>

#include "sf/negotiation/bench.hpp"

namespace cnp = sf::negotiation;

int main(int argc, char** argv) {
  const std::size_t negotiations = argc > 1 ? std::strtoul(argv[1], nullptr, 10) : 500;
  cnp::BenchOptions base;
  base.negotiations = negotiations == 0 ? 500 : negotiations;
  base.ddsperf = false;
  auto perf = cnp::run_ddsperf(base);
  if (perf) {
    std::printf("ddsperf ping/pong round trip (2 processes, loopback): p50 %.1f us, mean %.1f us\n",
                perf->p50_us, perf->mean_us);
  } else {
    std::printf("ddsperf not available: %s\n", perf.error().describe().c_str());
  }
  std::printf("%11s %9s %9s %9s %12s %12s %14s\n", "contractors", "p50 us", "p99 us", "mean us",
              "one-at-a-time/s", "8-in-flight/s", "p50 / ddsperf");
  for (std::size_t n : {1U, 4U, 16U, 64U}) {
    auto options = base;
    options.contractors = n;
    auto r = cnp::run_bench(options);
    if (!r) {
      std::printf("%11zu failed: %s\n", n, r.error().describe().c_str());
      continue;
    }
    const double ratio = perf && perf->p50_us > 0 ? r->latency.p50_us / perf->p50_us : 0.0;
    std::printf("%11zu %9.1f %9.1f %9.1f %15.0f %13.0f %13.1fx\n", n, r->latency.p50_us, r->latency.p99_us,
                r->latency.mean_us, r->sequential_per_s, r->pipelined_per_s, ratio);
  }
  return 0;
}
