// The line benchmark's run (line.hpp): `smartfactory line` as a child process, the orders fed to it,
// the order service's events followed in its log, ddsperf next to it.
#include <fstream>
#include <set>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "sf/bench/cnp.hpp"
#include "sf/bench/line.hpp"
#include "sf/bench/running_line.hpp"
#include "sf/core/clock.hpp"
#include "sf/core/process.hpp"

namespace sf::bench {
namespace {

using namespace std::chrono_literals;
namespace fs = std::filesystem;
using nlohmann::json;

constexpr auto kPollInterval = 100ms;

// The order service's own ready line (it started, or started again).
bool is_ready_line(const std::string& line) {
  const auto j = json::parse(line, nullptr, false);
  return !j.is_discarded() && j.is_object() && j.value("event", "") == "ready";
}

class LineBench {
 public:
  LineBench(const LineBenchOptions& o, const std::function<void(std::string_view)>& progress)
      : options_(o), progress_(progress) {}

  Result<LineBenchResult> run() {
    std::error_code ec;
    fs::create_directories(options_.run_dir, ec);
    if (ec) {
      return Error{Errc::io, fmt::format("{}: {}", options_.run_dir.string(), ec.message())};
    }
    auto layout = line::default_layout();
    if (!layout) {
      return layout.error();
    }
    orders_ = small_orders(layout->catalog, options_.orders, options_.seed);
    if (auto st = start_line(); !st) {
      return st.error();
    }
    // A line that stops making progress still gives the figures of the orders it finished.
    const auto st =
        options_.arrivals == Arrivals::file ? follow_until(orders_.size()) : submit_one_at_a_time();
    auto result = summarize(order_times(events_));
    if (!st) {
      result.incomplete = st.error().describe();
    }
    compare_with_ddsperf(result);
    report("stopping the line");
    line_.stop();
    return result;
  }

 private:
  void report(std::string_view what) const {
    if (progress_) {
      progress_(what);
    }
  }

  // The line, up, and where its order service logs its events.
  Status start_line() {
    const auto orders_file = options_.run_dir / "orders.yaml";
    std::ofstream(orders_file) << factory::orders_yaml(orders_);
    LineStartOptions start;
    start.smartfactory = options_.smartfactory;
    start.run_dir = options_.run_dir;
    start.extra_args = {"--opcua-base-port", "0"};
    if (options_.arrivals == Arrivals::file) {
      start.orders_file = orders_file;
    }
    auto line = RunningLine::start(start, progress_);
    if (!line) {
      return line.error();
    }
    line_ = std::move(*line);
    const auto* orders = line_.process("orders");
    if (orders == nullptr) {
      return Error{Errc::state, "the line has no order service"};
    }
    service_ = *orders;
    orders_log_.emplace(service_.log);
    report(fmt::format("the line is up; order service at {}", service_.opcua));
    return {};
  }

  // Reads the order service's new lines: its order events, and a second ready line (a restart,
  // which starts its clock and its orders afresh: the run is void).
  Status read_events() {
    for (const auto& l : orders_log_->read_new()) {
      if (auto e = parse_order_event(l)) {
        if (e->what == "done" || e->what == "failed") {
          finished_.insert(e->order);
          last_finish_ = clock_.now();
        } else if (e->what == "remade") {
          finished_.erase(e->order);
        }
        events_.push_back(std::move(*e));
      } else if (is_ready_line(l) && ++service_starts_ > 1) {
        return Error{Errc::state, "the order service restarted during the run (see its log)"};
      }
    }
    return {};
  }

  // Follows the events until `count` orders are finished.
  Status follow_until(std::size_t count) {
    last_finish_ = clock_.now();
    std::size_t reported = finished_.size();
    while (finished_.size() < count) {
      SF_TRY(read_events());
      if (finished_.size() != reported) {
        reported = finished_.size();
        report(fmt::format("{}/{} orders finished", reported, orders_.size()));
      }
      if (!line_.running()) {
        return Error{Errc::io, "the line ended during the run"};
      }
      if (clock_.now() - last_finish_ > options_.stall_limit) {
        return Error{Errc::timeout, fmt::format("no order finished for {} s ({} of {} finished)",
                                                options_.stall_limit.count(), finished_.size(), count)};
      }
      clock_.sleep_until(clock_.now() + kPollInterval);
    }
    return {};
  }

  // `smartfactory order` for each order once the one before is finished.
  Status submit_one_at_a_time() {
    for (std::size_t i = 0; i < orders_.size(); ++i) {
      SF_TRY(submit(orders_[i]));
      SF_TRY(follow_until(i + 1));
    }
    return {};
  }

  Status submit(const factory::Order& order) {
    ProcessOptions p;
    p.argv = {options_.smartfactory.string(),
              "order",
              "--server",
              service_.opcua,
              "--id",
              order.id,
              "--box",
              order.box_type};
    for (const auto& l : order.lines) {
      p.argv.insert(p.argv.end(), {"--candy", fmt::format("{}:{}", l.candy, l.quantity)});
    }
    p.err = Stdio::to_stdout();
    auto done = Process::run(std::move(p), 60s);
    if (!done) {
      return done.error();
    }
    if (!done->status.success()) {
      return Error{Errc::io, fmt::format("order {}: {}", order.id, done->out)};
    }
    return {};
  }

  // ddsperf ping with one pong on loopback (as the line's processes are configured), while the
  // line stands idle: the same host load as between the orders, without the orders' work.
  void compare_with_ddsperf(LineBenchResult& r) const {
    report(fmt::format("ddsperf ping/pong for {} s", options_.ddsperf_duration.count()));
    negotiation::BenchOptions d;
    d.contractors = 1;
    d.ddsperf_duration = options_.ddsperf_duration;
    auto perf = negotiation::run_ddsperf(d);
    if (!perf) {
      r.ddsperf_error = perf.error().describe();
      return;
    }
    r.ddsperf_rtt_p50_us = perf->round_trip.p50_us;
    if (perf->round_trip.p50_us > 0 && r.first_award_ms.samples > 0) {
      r.ratio = r.first_award_ms.p50 * 1e3 / perf->round_trip.p50_us;
      r.ratio_after_start = r.after_start_ms.p50 * 1e3 / perf->round_trip.p50_us;
    }
  }

  const LineBenchOptions& options_;
  const std::function<void(std::string_view)>& progress_;
  SteadyClock& clock_ = SteadyClock::instance();
  std::vector<factory::Order> orders_;
  RunningLine line_;
  LineProcessInfo service_;
  std::optional<FileLines> orders_log_;
  std::vector<LoggedOrderEvent> events_;
  std::set<std::string> finished_;
  Clock::time_point last_finish_{};
  int service_starts_ = 0;
};

}  // namespace

Result<LineBenchResult> run_line_bench(const LineBenchOptions& options,
                                       const std::function<void(std::string_view)>& progress) {
  if (options.orders == 0) {
    return Error{Errc::invalid_argument, "at least one order"};
  }
  LineBench bench(options, progress);
  return bench.run();
}

}  // namespace sf::bench
