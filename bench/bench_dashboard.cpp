// The dashboard end to end (issue 25): the prototype line as processes (`smartfactory line`,
// simulation) with orders that keep its smart robot picking, the line's cloud (gateway, historian,
// knowledge loop, dashboard) in this process, and headless Chromium on the operator page
// (bench/dashboard/browser.mjs). Three figures of one run:
//   - end to end: an axis position of the smart robot (read over its EtherCAT segment, written
//     into its OPC UA model) → the gateway (100 ms sampling and publishing, as the line's cloud)
//     → the dashboard's live stream (`series/<id>`) → the page's script; p50/p99 of page receive −
//     source time next to the gateway's notification latency (gateway receive − source time) of
//     the same samples, the peer. Goal: p99 ≤ 250 ms.
//   - page weight: the operator page loaded with the cache disabled, bytes as Chromium received
//     them (headers and bodies), next to the consumer page. Goal: ≤ 300 kB.
//   - time to first live value: navigation start → the first live update at the page's script
//     (and its frame), next to the page's load event.
// Source time: when the robot's OPC UA model wrote the value (CLOCK_REALTIME; dashboard.hpp).
//
// Usage: bench_dashboard [--samples 1000] [--seconds 600] [--loads 3] [--orders 6] [--candy gummy]...
//                        [--chromium PATH] [--web-root DIR]
// (follows the axes until SAMPLES updates reached the page, or SECONDS passed)
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <string>

#include <fmt/format.h>

#include "sf/bench/dashboard.hpp"
#include "sf/core/clock.hpp"
#include "sf/core/log.hpp"

namespace fs = std::filesystem;
namespace sb = sf::bench;

namespace {

constexpr const char* kUsage = R"(usage: bench_dashboard [options]
The operator dashboard end to end: starts the candy line as processes (smartfactory line) with
orders that keep its smart robot picking, the line's cloud in this process, and headless Chromium
on the operator page. Prints the latency of the robot's axis positions from their source time to
the page's script (p50/p99, goal p99 <= 250 ms) next to the gateway's notification latency of the
same samples; the operator page's weight (goal <= 300 kB) next to the consumer page; the time to
the first live value. Takes a few minutes; progress goes to stderr.
  --samples N     follow the axes until N updates reached the page (1000)
  --seconds S     or at most S seconds (600)
  --loads N       loads of the operator page for its weight and first live value (3)
  --orders N      orders of the largest box (6)
  --candy NAME    a candy type of those orders, repeatable (gummy)
  --chromium PATH the browser (default: Debian's chromium; also SF_CHROMIUM)
  --web-root DIR  the dashboard's pages (default: the built ones)
)";
constexpr double kGoalP99Ms = 250;
constexpr double kGoalPageKB = 300;

fs::path next_to_this_program(const char* relative) {
  std::error_code ec;
  return fs::read_symlink("/proc/self/exe", ec).parent_path() / relative;
}

sb::DashboardBenchOptions parse(int argc, char** argv) {
  sb::DashboardBenchOptions o;
  o.smartfactory = next_to_this_program("../apps/smartfactory/smartfactory");
  o.source_dir = SF_BENCH_SOURCE_DIR;
  o.web_root = SF_BENCH_WEB_ROOT;
  if (const char* c = std::getenv("SF_CHROMIUM")) {  // NOLINT(concurrency-mt-unsafe): before any thread
    o.chromium = c;
  }
  bool candy_given = false;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (i + 1 >= argc || !arg.starts_with("--")) {
      (arg == "--help" ? std::cout : std::cerr) << kUsage;
      std::exit(arg == "--help" ? 0 : 2);  // NOLINT(concurrency-mt-unsafe): before any thread
    }
    const std::string value = argv[++i];
    if (arg == "--samples") {
      o.samples = std::stoul(value);
    } else if (arg == "--seconds") {
      o.seconds = std::stoi(value);
    } else if (arg == "--loads") {
      o.loads = std::max(1, std::stoi(value));
    } else if (arg == "--orders") {
      o.orders = std::stoul(value);
    } else if (arg == "--candy") {
      if (!candy_given) {
        o.candy.clear();
        candy_given = true;
      }
      o.candy.push_back(value);
    } else if (arg == "--chromium") {
      o.chromium = value;
    } else if (arg == "--web-root") {
      o.web_root = value;
    } else {
      std::cerr << "bench_dashboard: unknown option " << arg << "\n";
      std::exit(2);  // NOLINT(concurrency-mt-unsafe): before any thread
    }
  }
  return o;
}

double kb(std::uint64_t bytes) {
  return static_cast<double>(bytes) / 1000.0;
}

void row(std::string_view what, const sb::Percentiles& p) {
  fmt::print("  {:<52} {:>8.1f} {:>8.1f} {:>8}\n", what, p.p50, p.p99, p.samples);
}

void print_latency(const sb::DashboardBenchResult& r) {
  const auto& l = r.latency;
  const auto& w = r.browser.window;
  fmt::print(
      "{} axis positions of {} (Tags/axisN.position), sampling {} ms, publishing {} ms; followed {:.0f} s\n",
      r.axes, r.robot, r.sampling_ms, r.publishing_ms, (w.to_ms - w.from_ms) / 1000.0);
  fmt::print("  {:<52} {:>8} {:>8} {:>8}\n", "latency from the source time", "p50 ms", "p99 ms", "samples");
  row("page script (Chromium, the dashboard's WebSocket)", l.page_ms);
  row("plain WebSocket client (Node's ws, no browser)", l.client_ms);
  row("gateway notification, the same samples (peer)", l.gateway_same_ms);
  row("gateway notification, every sample of that span", l.gateway_all_ms);
  row("page after the gateway (dashboard, WebSocket, page)", l.page_after_gateway_ms);
  fmt::print(
      "  page samples without the gateway's: {}; live stream: {} updates sent, {} dropped (coalesced)\n",
      l.unpaired, r.live.sent, r.live.dropped);
  fmt::print("  goal p99 <= {:.0f} ms: {}\n", kGoalP99Ms,
             l.page_ms.samples == 0 ? "no samples" : (l.page_ms.p99 <= kGoalP99Ms ? "met" : "missed"));
}

void print_load(std::string_view label, const sb::PageLoad& p) {
  fmt::print("  {:<28} {:>7.1f} kB in {:>2} requests (REST API {:.1f} kB, vendor/ {:.1f} kB)\n", label,
             kb(p.bytes), p.requests, kb(p.api_bytes), kb(p.vendor_bytes));
  for (const auto& f : p.failed) {
    fmt::print("    failed: {}\n", f);
  }
}

// Median and maximum of one time over the operator page's loads.
void time_row(std::string_view what, const std::vector<sb::PageLoad>& loads,
              std::optional<double> sb::PageLoad::*field) {
  std::vector<double> t;
  for (const auto& l : loads) {
    if (l.*field) {
      t.push_back(*(l.*field));
    }
  }
  if (t.empty()) {
    fmt::print("  {:<44} {:>9} {:>9}\n", what, "-", "-");
    return;
  }
  std::sort(t.begin(), t.end());
  fmt::print("  {:<44} {:>9.0f} {:>9.0f}\n", what, t[t.size() / 2], t.back());
}

void print_pages(const sb::BrowserResult& b) {
  const auto& first = b.operator_loads.front();
  fmt::print(
      "page weight (cache disabled; bytes as Chromium received them: headers and bodies; 1 kB = 1000 B)\n");
  print_load("operator.html", first);
  fmt::print("  {:<28} {:>7.1f} kB (uPlot.esm.js alone)\n", "", kb(first.uplot_js_bytes));
  print_load("index.html (consumer, peer)", b.consumer);
  fmt::print("  goal operator page <= {:.0f} kB: {}\n", kGoalPageKB,
             kb(first.bytes) <= kGoalPageKB ? "met" : "missed");
  fmt::print("time to first live value, operator page, ms after navigation start ({} loads)\n",
             b.operator_loads.size());
  fmt::print("  {:<44} {:>9} {:>9}\n", "", "median", "max");
  time_row("load event (peer)", b.operator_loads, &sb::PageLoad::load_ms);
  time_row("live stream open", b.operator_loads, &sb::PageLoad::ws_open_ms);
  time_row("first live update at the page's script", b.operator_loads, &sb::PageLoad::first_live_ms);
  time_row("the frame after it", b.operator_loads, &sb::PageLoad::first_live_frame_ms);
}

}  // namespace

int main(int argc, char** argv) {
  std::setvbuf(stdout, nullptr, _IOLBF, 0);  // lines as they come: a run takes minutes
  (void)sf::log::set_level("error");         // the cloud here: its alarms are the line's business
  auto o = parse(argc, argv);
  if (auto st = sb::check_prerequisites(o); !st) {
    fmt::print("bench_dashboard: skipped: {}\n", st.error().message);
    return 0;
  }
  std::string dir = (fs::temp_directory_path() / "sf-bench-dashboard-XXXXXX").string();
  if (::mkdtemp(dir.data()) == nullptr) {
    std::fprintf(stderr, "bench_dashboard: cannot make a run directory\n");
    return 1;
  }
  o.run_dir = dir;
  auto& clock = sf::SteadyClock::instance();
  const auto t0 = clock.now();
  auto r = sb::run_dashboard_bench(o, [&](std::string_view what) {
    fmt::print(stderr, "{:7.1f} s  {}\n", std::chrono::duration<double>(clock.now() - t0).count(), what);
  });
  if (!r) {
    fmt::print(stderr, "bench_dashboard: {} (run directory {})\n", r.error().describe(), dir);
    return 1;
  }
  fmt::print(
      "the prototype line as processes (`smartfactory line`, simulation), its cloud (gateway, historian, "
      "knowledge loop, dashboard) in this process, Chromium {} on the operator page\n",
      r->browser.chromium);
  fmt::print(
      "source time: when {}'s OPC UA model wrote the value (CLOCK_REALTIME); received: the gateway's live "
      "bus "
      "(CLOCK_REALTIME), the page's script (performance.timeOrigin + now(); page − system clock {:.1f} ms)\n",
      r->robot, r->browser.clock_offset_ms);
  print_latency(*r);
  if (!r->browser.operator_loads.empty()) {
    print_pages(r->browser);
  }
  fmt::print("run directory: {} (every process's log)\n", dir);
  return r->latency.page_ms.samples > 0 ? 0 : 1;
}
