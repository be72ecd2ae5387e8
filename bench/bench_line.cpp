// The factory as processes on loopback (`smartfactory line`, the default layout, no cloud): per
// order accepted → first award (its upload, won by the uploader's gateway in the Contract Net) and
// accepted → done (lead time), p50/p99, from the order service's event lines; next to Cyclone's
// ddsperf ping/pong round trip (one pong, loopback) measured in the same run while the line stands
// idle, as a ratio. A Contract Net award is at best two round trips (ANNOUNCE → BID, AWARD →
// CONFIRM). "after what let it start": from the latest event of another order before the award
// (a place in work freed, the uploader's belt cleared) to the award: the first award without the
// wait for the line.
//
// Orders: ORDERS small orders (the smallest box, one candy of one or two types, seeded), either all
// in the line's order file at the start (`file`: the first award includes the queue) or handed to
// the order service one at a time with `smartfactory order`, the next once the one before is done
// (`one-at-a-time`: no queue). The run directory keeps every process's log.
//
// Usage: bench_line [ORDERS] [file|one-at-a-time] [DDSPERF_SECONDS]   (default 30 file 5)
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>

#include <fmt/format.h>

#include "sf/bench/line.hpp"
#include "sf/core/clock.hpp"

namespace fs = std::filesystem;
namespace sb = sf::bench;

namespace {

void print(const sb::LineBenchResult& r, const sb::LineBenchOptions& o) {
  fmt::print("orders: {} done, {} failed of {} in {:.1f} s\n", r.done, r.failed, o.orders, r.span_s);
  fmt::print("accepted → first award:        p50 {:10.1f} ms  p99 {:10.1f} ms  ({} orders)\n",
             r.first_award_ms.p50, r.first_award_ms.p99, r.first_award_ms.samples);
  std::string by;
  for (const auto& [what, n] : r.started_by) {
    by += fmt::format("{}{} {}", by.empty() ? "" : ", ", what, n);
  }
  fmt::print("  after what let it start:     p50 {:10.1f} ms  p99 {:10.1f} ms  (the event before: {})\n",
             r.after_start_ms.p50, r.after_start_ms.p99, by);
  fmt::print("accepted → done (lead time):   p50 {:10.1f} s   p99 {:10.1f} s\n", r.lead_time_s.p50,
             r.lead_time_s.p99);
  if (!r.ddsperf_rtt_p50_us) {
    fmt::print("ddsperf: no round trip ({}); no ratio\n", r.ddsperf_error);
    return;
  }
  const double rtt = *r.ddsperf_rtt_p50_us;
  fmt::print("ddsperf ping/pong round trip (1 pong, loopback, line idle): p50 {:.1f} us\n", rtt);
  fmt::print("ratio first award p50 / round trip p50: {:.0f}x; after what let it start: {:.0f}x\n",
             r.ratio.value_or(0), r.ratio_after_start.value_or(0));
  const double best = sb::kRoundTripsPerAward * rtt;
  fmt::print(
      "an award at best: {} round trips (ANNOUNCE → BID, AWARD → CONFIRM) = {:.1f} us; "
      "after what let it start the award p50 is {:.0f}x that\n",
      sb::kRoundTripsPerAward, best, r.after_start_ms.p50 * 1e3 / best);
}

fs::path next_to_this_program(const char* relative) {
  std::error_code ec;
  return fs::read_symlink("/proc/self/exe", ec).parent_path() / relative;
}

}  // namespace

int main(int argc, char** argv) {
  std::setvbuf(stdout, nullptr, _IOLBF, 0);  // lines as they come: a run takes minutes
  sb::LineBenchOptions o;
  o.orders = argc > 1 ? std::strtoul(argv[1], nullptr, 10) : 30;
  const std::string arrivals = argc > 2 ? argv[2] : "file";
  if (arrivals != "file" && arrivals != "one-at-a-time") {
    std::fprintf(stderr, "usage: bench_line [ORDERS] [file|one-at-a-time] [DDSPERF_SECONDS]\n");
    return 2;
  }
  o.arrivals = arrivals == "file" ? sb::Arrivals::file : sb::Arrivals::one_at_a_time;
  o.ddsperf_duration = std::chrono::seconds{argc > 3 ? std::strtol(argv[3], nullptr, 10) : 5};
  o.smartfactory = next_to_this_program("../apps/smartfactory/smartfactory");
  std::string dir = (fs::temp_directory_path() / "sf-bench-line-XXXXXX").string();
  if (::mkdtemp(dir.data()) == nullptr) {
    std::fprintf(stderr, "bench_line: cannot make a run directory\n");
    return 1;
  }
  o.run_dir = dir;
  fmt::print(
      "the prototype line as processes on loopback (`smartfactory line`, no cloud); {} small orders "
      "(seed {}), {}\n",
      o.orders, o.seed, sb::to_string(o.arrivals));
  auto& clock = sf::SteadyClock::instance();
  const auto t0 = clock.now();
  auto r = sb::run_line_bench(o, [&](std::string_view what) {
    fmt::print(stderr, "{:7.1f} s  {}\n", std::chrono::duration<double>(clock.now() - t0).count(), what);
  });
  if (!r) {
    fmt::print(stderr, "bench_line: {} (run directory {})\n", r.error().describe(), dir);
    return 1;
  }
  print(*r, o);
  fmt::print("run directory: {} (every process's log)\n", dir);
  if (!r->incomplete.empty()) {
    fmt::print("incomplete: {}\n", r->incomplete);
    return 1;
  }
  return 0;
}
