// The factory as processes (`smartfactory line` on loopback, paper §VII) as a benchmark: per order,
// accepted → first award (the first Contract Net operation it won, the uploader's) and accepted →
// done (lead time), read from the order service's own event lines (`smartfactory orders --json`
// prints every OrderEvent with its time; the line keeps that output in log/orders.log). In the same
// run Cyclone's ddsperf ping/pong round trip on loopback (sf::negotiation::run_ddsperf), so the
// award latency comes with its ratio to one DDS round trip: a Contract Net award is at best two
// (ANNOUNCE → BID, AWARD → CONFIRM).
#pragma once

#include <chrono>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "sf/core/result.hpp"
#include "sf/factory/order.hpp"
#include "sf/line/layout.hpp"

namespace sf::bench {

// A Contract Net award at best: ANNOUNCE → BID, AWARD → CONFIRM.
inline constexpr int kRoundTripsPerAward = 2;

// One `{"event":"order",...}` line of `smartfactory orders --json`.
struct LoggedOrderEvent {
  double t = 0;  // seconds since the order service started
  std::string order;
  std::string what;  // accepted, awarded, transported, done, failed, ... (factory::OrderEvent)
  std::string machine;
  std::string detail;
};

// The order event of `line`; nullopt for any other line (other events, log lines, partial lines).
std::optional<LoggedOrderEvent> parse_order_event(std::string_view line);

// One order's times, in seconds since the service started; from its events in their order.
struct OrderTimes {
  std::string order;
  double accepted = 0;
  std::optional<double> first_award;
  std::optional<double> done;  // or failed
  bool failed = false;
  // The latest event of another order before the first award, or the acceptance if that came
  // later: what let the order start (a place in work freed, its first belt cleared), so
  // first_award - started_at is the negotiation without the wait before it.
  double started_at = 0;
  std::string started_by;  // that event's `what` ("done", "transported", ...; "accepted")
};

// The orders of `events` in the order they were accepted.
std::vector<OrderTimes> order_times(const std::vector<LoggedOrderEvent>& events);

// `count` small orders (seed): the catalog's smallest box with one candy of one or two types, so
// that a run of dozens takes minutes; ids <prefix>-1, -2, ...
std::vector<factory::Order> small_orders(const line::Catalog& catalog, std::size_t count, std::uint64_t seed,
                                         const std::string& prefix = "bench");

// The complete lines appended to a file since the last call (a file other processes write).
class FileLines {
 public:
  explicit FileLines(std::filesystem::path path) : path_(std::move(path)) {}
  std::vector<std::string> read_new();

 private:
  std::filesystem::path path_;
  std::uintmax_t offset_ = 0;
  std::string partial_;
};

enum class Arrivals {
  file,           // every order in the line's order file, taken at the service's start
  one_at_a_time,  // `smartfactory order` for the next once the one before is done: no queueing
};
std::string_view to_string(Arrivals arrivals);

struct LineBenchOptions {
  std::filesystem::path smartfactory;  // the binary
  std::filesystem::path run_dir;       // the line's run directory and the bench's files (created)
  std::size_t orders = 30;
  std::uint64_t seed = 24;
  Arrivals arrivals = Arrivals::file;
  std::chrono::seconds ddsperf_duration{5};
  std::chrono::seconds stall_limit{600};  // no order finished for this long: the run fails
};

struct Percentiles {
  std::size_t samples = 0;
  double p50 = 0;
  double p99 = 0;
};

struct LineBenchResult {
  std::size_t done = 0;
  std::size_t failed = 0;
  double span_s = 0;                                            // first acceptance → last order finished
  Percentiles first_award_ms;                                   // accepted → first award
  Percentiles after_start_ms;                                   // OrderTimes::started_at → first award
  std::vector<std::pair<std::string, std::size_t>> started_by;  // counts by OrderTimes::started_by
  Percentiles lead_time_s;                                      // accepted → done, of the orders done
  std::optional<double> ddsperf_rtt_p50_us;
  std::optional<double> ratio;              // first award p50 / ddsperf round trip p50
  std::optional<double> ratio_after_start;  // after_start p50 / ddsperf round trip p50
  std::string ddsperf_error;                // why there is no round trip
  std::string incomplete;  // why the run ended before every order was finished (empty: it did not)
};

Percentiles percentiles(std::vector<double> samples);
// What the times say, without the ddsperf figures.
LineBenchResult summarize(const std::vector<OrderTimes>& orders);

// Starts the line, feeds it the orders, follows the order service's events until every order is
// done or failed (or none finishes for stall_limit: then the figures are of those finished, and
// `incomplete` says why), then runs ddsperf while the line stands idle, and stops the line.
// Progress goes to `progress`. An error only when the line could not be started.
Result<LineBenchResult> run_line_bench(const LineBenchOptions& options,
                                       const std::function<void(std::string_view)>& progress = {});

}  // namespace sf::bench
