// The Contract Net benchmark behind `smartfactory cnp bench`, bench/bench_cnp.sh and bench_cnp: a
// harness next to the benchmarks, not part of the negotiation library. Negotiation latency
// (ANNOUNCE → confirmed AWARD, one negotiation at a time) and throughput (a window of negotiations
// in flight) against N contractors over DDS on loopback, the contractors either in this process
// or each in its own process. In the same run it measures Cyclone's own ddsperf ping/pong round
// trip with the same configuration, so the figure comes with its ratio to one DDS round trip
// (machines are shared and noisy).
#pragma once

#include <chrono>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <string_view>

#include "sf/core/process.hpp"
#include "sf/core/result.hpp"
#include "sf/negotiation/dds_transport.hpp"

namespace sf::negotiation {

// The Linux scheduling policy of the contractor processes and of ddsperf's pongs (never of the
// product or of ddsperf's ping). On a host with fewer cores than processes, a contractor woken by
// the manager's fan-out preempts the manager in the middle of it (CFS wake-up preemption), so the
// fan-out's time includes the work of every contractor woken so far; in the factory each machine
// runs on its own controller. SCHED_BATCH processes do not preempt on wake-up (sched(7)): they
// run on another core or when the manager's thread blocks. Applied alike to both sides.
using SchedulingPolicy = sf::SchedulingPolicy;

struct BenchOptions {
  std::size_t contractors = 4;
  std::size_t negotiations = 1000;  // per phase (latency, throughput)
  bool processes = false;           // each contractor in its own process
  std::string agent_binary;         // the smartfactory binary (for processes)
  std::size_t window = 8;           // negotiations in flight in the throughput phase
  std::size_t warmup = 20;
  std::chrono::nanoseconds spin{0};  // executor spin before blocking (here and in contractor processes)
  bool inline_delivery = true;       // handle messages on the DDS thread (RunOptions), here and in processes
  SchedulingPolicy contractor_scheduling = SchedulingPolicy::batch;
  DdsSettings dds;
  bool ddsperf = true;
  std::string ddsperf_binary = "ddsperf";
  std::chrono::seconds ddsperf_duration{4};
};

struct LatencyStats {
  std::size_t samples = 0;
  double mean_us = 0;
  double p50_us = 0;
  double p90_us = 0;
  double p99_us = 0;
  double max_us = 0;
};

struct BenchResult {
  std::size_t contractors = 0;
  std::size_t negotiations = 0;
  bool processes = false;
  SchedulingPolicy contractor_scheduling = SchedulingPolicy::normal;  // of contractor and pong processes
  std::size_t window = 0;
  LatencyStats latency;         // one negotiation at a time
  double sequential_per_s = 0;  // one at a time
  double pipelined_per_s = 0;   // `window` at a time
  std::uint64_t renegotiations = 0;
  std::uint64_t failed = 0;
  std::optional<double> ddsperf_rtt_p50_us;   // ddsperf's fan-out round trip, median (FanOutRoundTrip)
  std::optional<double> ddsperf_rtt_mean_us;  // ddsperf's fan-out round trip, mean: one ping cycle
  std::optional<double> ratio_p50;            // latency p50 / ddsperf round-trip p50
  std::optional<double> ratio_mean;           // latency mean / ddsperf ping cycle
  // CPU time (user + system) of every process taking part (product, contractors / ping, pongs)
  // per negotiation of the one-at-a-time phase, and per ddsperf fan-out round trip: what a
  // negotiation costs where the processes outnumber the cores.
  std::optional<double> cpu_us_per_negotiation;
  std::optional<double> ddsperf_cpu_us_per_round_trip;
  std::optional<double> cpu_ratio;
};

// ddsperf's round trip from one ping to all its pongs, read from ping's output.
//
// ddsperf ping prints, per second and per pong, statistics of HALF the round trip: its pong
// handler records (receive time - the ping's source timestamp) / 2 (ddsperf.c, process_pong),
// a one-way latency estimate. A round trip is twice what it prints; with one pong, twice the
// printed mean matches 1 s / pings per second.
struct FanOutRoundTrip {
  // Twice the median over the report seconds of the slowest pong's median: a lower bound of
  // the median fan-out round trip (the slowest answer to each ping may come from any pong).
  double p50_us = 0;
  // The mean ping cycle: ping sends the next ping once every pong has answered, so a cycle is
  // one fan-out round trip; report time / pings every pong answered, over the reports after the
  // first (whose interval starts before the pings do). nullopt with fewer than two reports.
  std::optional<double> mean_us;
  std::size_t pings = 0;  // pings every pong answered, over all reports
};

struct DdsperfResult {
  FanOutRoundTrip round_trip;
  std::optional<double> cpu_us_per_round_trip;  // ping's and pongs' CPU time / pings
};

LatencyStats latency_stats(std::vector<double> samples_us);

// Progress lines go to `progress` (e.g. stderr).
Result<BenchResult> run_bench(const BenchOptions& options,
                              const std::function<void(std::string_view)>& progress = {});

// ddsperf ping/pong on loopback with `settings`' network configuration, in a domain of its own,
// at the negotiation's fan-out: one pong process per contractor (the same fan-out as a
// negotiation's ANNOUNCE); a ping is sent when every pong has answered.
Result<DdsperfResult> run_ddsperf(const BenchOptions& options);
// Reads ddsperf ping's output (see FanOutRoundTrip); nullopt when it holds no round-trip line.
std::optional<FanOutRoundTrip> parse_ddsperf_output(const std::string& path);

// CPU time (user + system) a running process has used, summed over its threads from
// /proc/<pid>/task/*/schedstat (nanoseconds; threads that ended are not counted); nullopt when
// the process is gone or /proc has no schedstat.
std::optional<std::chrono::nanoseconds> process_cpu_time(int pid);

}  // namespace sf::negotiation
