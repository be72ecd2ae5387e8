// `smartfactory cnp bench`: the Contract Net benchmark (bench/cnp) from the command line, as
// bench/bench_cnp.sh runs it; prints its result as text or one JSON line.
#include "agent_common.hpp"

#include <unistd.h>

#include <array>
#include <iostream>
#include <memory>
#include <optional>

#include <fmt/format.h>

#include "sf/bench/cnp.hpp"

namespace sf::app::agents {
namespace {

struct BenchCliOptions {
  DdsCliOptions dds;
  unsigned contractors = 4;
  unsigned negotiations = 1000;
  unsigned window = 8;
  bool processes = false;
  bool no_ddsperf = false;
  unsigned ddsperf_s = 4;
  std::string contractor_sched = "batch";
};

std::string self_binary() {
  std::array<char, 4096> buf{};
  const auto n = ::readlink("/proc/self/exe", buf.data(), buf.size() - 1);
  return n > 0 ? std::string(buf.data(), static_cast<std::size_t>(n)) : std::string{};
}

json bench_json(const cnp::BenchResult& r) {
  json j{{"contractors", r.contractors},
         {"negotiations", r.negotiations},
         {"processes", r.processes},
         {"contractor_sched", sf::to_string(r.contractor_scheduling)},
         {"latency_us",
          {{"p50", r.latency.p50_us},
           {"p90", r.latency.p90_us},
           {"p99", r.latency.p99_us},
           {"mean", r.latency.mean_us},
           {"max", r.latency.max_us},
           {"samples", r.latency.samples}}},
         {"sequential_per_s", r.sequential_per_s},
         {"pipelined_per_s", r.pipelined_per_s},
         {"window", r.window},
         {"renegotiations", r.renegotiations},
         {"failed", r.failed}};
  const auto value = [](const std::optional<double>& v) { return v ? json(*v) : json(nullptr); };
  j["ddsperf_rtt_p50_us"] = value(r.ddsperf_rtt_p50_us);
  j["ddsperf_rtt_mean_us"] = value(r.ddsperf_rtt_mean_us);
  j["ratio_p50"] = value(r.ratio_p50);
  j["ratio_mean"] = value(r.ratio_mean);
  j["cpu_us_per_negotiation"] = value(r.cpu_us_per_negotiation);
  j["ddsperf_cpu_us_per_round_trip"] = value(r.ddsperf_cpu_us_per_round_trip);
  j["cpu_ratio"] = value(r.cpu_ratio);
  return j;
}

int run_bench_cmd(const BenchCliOptions& o) {
  cnp::BenchOptions b;
  b.contractors = o.contractors;
  b.negotiations = o.negotiations;
  b.window = o.window;
  b.processes = o.processes;
  b.agent_binary = self_binary();
  b.dds = dds_settings(o.dds);
  b.ddsperf = !o.no_ddsperf;
  b.ddsperf_duration = std::chrono::seconds{o.ddsperf_s};
  b.spin = std::chrono::microseconds{o.dds.spin_us};
  b.inline_delivery = run_options(o.dds).inline_delivery;
  b.contractor_scheduling =
      o.contractor_sched == "batch" ? cnp::SchedulingPolicy::batch : cnp::SchedulingPolicy::normal;
  auto r = cnp::run_bench(b, [](std::string_view line) { std::cerr << "cnp bench: " << line << "\n"; });
  if (!r) {
    std::cerr << "cnp bench: " << r.error().describe() << "\n";
    return kExitFailure;
  }
  if (o.dds.json) {
    emit(bench_json(*r));
    return kExitOk;
  }
  say(fmt::format(
      "{} contractors ({}), ANNOUNCE -> confirmed AWARD: p50 {:.1f} us, p99 {:.1f} us, mean {:.1f} us",
      r->contractors, r->processes ? "one process each" : "in this process", r->latency.p50_us,
      r->latency.p99_us, r->latency.mean_us));
  say(fmt::format("  {:.0f} negotiations/s one at a time, {:.0f}/s with {} in flight", r->sequential_per_s,
                  r->pipelined_per_s, r->window));
  if (r->ddsperf_rtt_p50_us) {
    say(fmt::format("  ddsperf round trip to {} pongs p50 {:.1f} us: negotiation p50 = {:.2f} round trips",
                    r->contractors, *r->ddsperf_rtt_p50_us, r->ratio_p50.value_or(0)));
  }
  if (r->ddsperf_rtt_mean_us) {
    say(fmt::format("  ddsperf ping cycle (mean round trip) {:.1f} us: negotiation mean = {:.2f} round trips",
                    *r->ddsperf_rtt_mean_us, r->ratio_mean.value_or(0)));
  }
  if (r->cpu_us_per_negotiation) {
    say(fmt::format("  CPU time of all processes: {:.1f} us per negotiation", *r->cpu_us_per_negotiation));
  }
  if (r->cpu_ratio) {
    say(fmt::format("  ddsperf: {:.1f} us per round trip: negotiation = {:.1f} round trips of CPU",
                    r->ddsperf_cpu_us_per_round_trip.value_or(0), *r->cpu_ratio));
  }
  return kExitOk;
}

}  // namespace

void register_bench(CLI::App& group, CommandResult& result) {
  auto o = std::make_shared<BenchCliOptions>();
  auto* cmd = group.add_subcommand(
      "bench",
      "Negotiation latency (ANNOUNCE -> confirmed AWARD) and rate against N contractors, next to "
      "ddsperf's ping/pong round trip at the same fan-out (one pong process per contractor) measured in the "
      "same run");
  cmd->add_option("--contractors", o->contractors, "Contractors (machines) bidding on every call")
      ->check(CLI::Range(1U, 200U))
      ->capture_default_str();
  cmd->add_option("--negotiations", o->negotiations, "Negotiations per phase (latency, throughput)")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  cmd->add_option("--window", o->window, "Negotiations in flight in the throughput phase")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  cmd->add_flag("--processes", o->processes,
                "Run each contractor as its own process (smartfactory agent machine)");
  cmd->add_flag("--no-ddsperf", o->no_ddsperf, "Skip the ddsperf comparison");
  cmd->add_option("--ddsperf-seconds", o->ddsperf_s, "How long ddsperf ping runs")->capture_default_str();
  cmd->add_option("--contractor-sched", o->contractor_sched,
                  "Linux scheduling policy of the contractor and ddsperf pong processes (never of the "
                  "product or ping): 'batch' (SCHED_BATCH) keeps a contractor woken by the product's "
                  "fan-out from preempting the product in the middle of it, as on a host with a core per "
                  "machine; 'normal' (SCHED_OTHER) lets it")
      ->check(CLI::IsMember({"batch", "normal"}))
      ->capture_default_str();
  add_dds_options(*cmd, o->dds);
  cmd->callback([o, &result] { result.exit_code = run_bench_cmd(*o); });
}

}  // namespace sf::app::agents
