// The dashboard end to end as a benchmark (issue 25, docs/performance.md "Dashboard end to end"):
// the line as processes (`smartfactory line`, simulation) with orders that keep its smart robot
// picking; the cloud of `smartfactory line --historian` (gateway, historian, knowledge loop,
// dashboard, configured by factory::cloud_config_yaml) in this process, so that the gateway's own
// live bus shows when each sample arrived; headless Chromium (bench/dashboard/browser.mjs) on the
// operator page, subscribed to the robot's axis positions (`series/<id>`) on the page's own live
// stream.
//
// Source time: the smart robot's OPC UA model stamps each value when it writes it into its
// address space (MachineHost's publish timer, every 10 ms, from the controller thread's snapshot of
// its 1 kHz EtherCAT cycle, refreshed every 10 ms) with CLOCK_REALTIME. The gateway's and the
// page's receive times are CLOCK_REALTIME too (system_clock here; Chromium's
// performance.timeOrigin + performance.now()), all on one host.
#pragma once

#include <chrono>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "sf/bench/line.hpp"
#include "sf/core/result.hpp"

namespace sf::bench {

// One axis sample at the gateway: when the value was written on the machine and when the
// gateway's live bus had it (µs since the epoch, CLOCK_REALTIME).
struct GatewaySample {
  std::int64_t series{};
  std::int64_t source_us{};
  std::int64_t received_us{};
};

// The same sample at the page: its source time as the live stream carries it (whole ms) and
// when the page's script had it (ms since the epoch, fractional).
struct PageSample {
  std::int64_t series{};
  std::int64_t source_ms{};
  double received_ms{};
};

struct LatencyFigures {
  Percentiles page_ms;                // page receive − source time (exact source time when paired)
  Percentiles client_ms;              // the same at a plain WebSocket client outside the browser
  Percentiles gateway_same_ms;        // gateway receive − source time of the samples the page had
  Percentiles gateway_all_ms;         // the same of every sample the gateway had in the page's window
  Percentiles page_after_gateway_ms;  // page receive − gateway receive (dashboard, WebSocket, browser)
  std::size_t unpaired = 0;           // page and client samples the gateway had not recorded
};

// The wall-clock window (ms since the epoch) the page followed the series in.
struct Window {
  double from_ms = 0;
  double to_ms = 0;
};

// Pairs each page (and client) sample with the gateway's of the same series and source
// millisecond; gateway samples whose source time lies outside the page's window count nowhere.
LatencyFigures latency_figures(const std::vector<GatewaySample>& gateway, const std::vector<PageSample>& page,
                               const std::vector<PageSample>& client, Window window);

// What one load of a page transferred (Chromium's encodedDataLength: headers and body) and when
// it came to life (ms after navigation start; nullopt: did not happen).
struct PageLoad {
  std::string path;
  std::size_t requests = 0;
  std::uint64_t bytes = 0;         // everything
  std::uint64_t api_bytes = 0;     // of that, fetch/XHR (the REST API)
  std::uint64_t vendor_bytes = 0;  // of that, vendor/ (uPlot from npm)
  std::uint64_t uplot_js_bytes = 0;
  std::vector<std::string> failed;  // requests that failed, with Chromium's reason
  std::optional<double> load_ms;
  std::optional<double> ws_open_ms;
  std::optional<double> first_live_ms;        // first live update's message reached the page's scripts
  std::optional<double> first_live_frame_ms;  // the frame after it (what the handler changed painted)
};

struct BrowserResult {
  std::string chromium;
  std::vector<PageLoad> operator_loads;
  PageLoad consumer;
  std::vector<PageSample> samples;
  std::vector<PageSample> client_samples;  // Node's ws on the same topics (its performance clock)
  Window window;
  double clock_offset_ms = 0;  // the page's wall clock − Date.now() at the end
};

// The {"result": {...}} line browser.mjs prints; nullopt for any other line.
std::optional<BrowserResult> parse_browser_result(std::string_view line);

struct DashboardBenchOptions {
  std::filesystem::path smartfactory;  // the binary
  std::filesystem::path run_dir;       // the line's run directory, the cloud's files (created)
  std::filesystem::path source_dir;    // the repository: bench/dashboard/browser.mjs, node_modules
  std::filesystem::path web_root;      // the pages (the build's dashboard_web)
  std::string chromium = "/usr/bin/chromium";
  std::size_t samples = 1000;  // page samples to follow the axes for,
  int seconds = 600;           // or at most this long
  int loads = 3;               // of the operator page
  std::size_t orders = 6;
  // The candy types of the orders' boxes (filled evenly); empty: those of the robot's dispensers.
  // Gummy: on the default layout scara-robot-1's bid beats toshiba's (the other gummy dispenser)
  // when both are free, while denso's beats it for chocolate.
  std::vector<std::string> candy{"gummy"};
  std::chrono::seconds move_limit{300};  // for the robot's first moves after the line is up
};

struct LiveStreamCounts {
  std::uint64_t sent = 0;
  std::uint64_t dropped = 0;  // coalesced: replaced by a newer value of their topic unsent
};

struct DashboardBenchResult {
  std::string robot;
  std::size_t axes = 0;
  double sampling_ms = 0;  // the gateway's subscription of the robot's server
  double publishing_ms = 0;
  BrowserResult browser;
  LatencyFigures latency;
  LiveStreamCounts live;
};

// What the run needs besides this build: Chromium, node with puppeteer-core (scripts/setup), the
// web root with the pages. Errc::not_found naming the first one missing.
Status check_prerequisites(const DashboardBenchOptions& options);

Result<DashboardBenchResult> run_dashboard_bench(const DashboardBenchOptions& options,
                                                 const std::function<void(std::string_view)>& progress = {});

}  // namespace sf::bench
