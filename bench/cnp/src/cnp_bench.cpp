#include "sf/bench/cnp.hpp"

#include <unistd.h>

#include <algorithm>
#include <set>
#include <span>

#include <fmt/format.h>

#include "processes.hpp"
#include "sf/bench/percentile.hpp"
#include "sf/dds/config.hpp"
#include "sf/negotiation/agents.hpp"

namespace sf::negotiation {
namespace {

using namespace std::chrono_literals;
using detail::cpu_time_of;
using detail::microseconds;

// The benchmark's manager as an agent, so that run_agents drives it with the contractors.
class ManagerAgent final : public Agent {
 public:
  ManagerAgent(Manager& manager, ProductEndpoints& endpoints) : manager_(manager), endpoints_(endpoints) {}
  void tick() override {
    manager_.tick();
    endpoints_.flush_ended();
  }
  [[nodiscard]] std::optional<Clock::time_point> next_deadline() const override {
    return earliest(manager_.next_deadline(), endpoints_.ends_due());
  }

 private:
  Manager& manager_;
  ProductEndpoints& endpoints_;
};

// The side of the benchmark that negotiates: a product with one manager.
class Driver {
 public:
  Driver(const BenchOptions& o, const DdsSettings& s) : options_(o), settings_(s) {}
  Driver(const Driver&) = delete;
  Driver& operator=(const Driver&) = delete;
  ~Driver() {
    // Nothing may run inline on a DDS thread while the members go.
    const auto strand = executor_.hold();
    executor_.set_inline(false);
  }

  Status setup(const std::function<void(std::string_view)>& progress) {
    executor_.set_spin(options_.spin);
    auto ep = ProductEndpoints::create(settings_, "bench", {"OP1"}, executor_, clock_, false);
    if (!ep) {
      return ep.error();
    }
    endpoints_ = std::move(*ep);
    ManagerConfig mc;
    mc.bid_window = 2s;
    mc.confirm_window = 2s;
    mc.max_rounds = 0;
    manager_ = std::make_unique<Manager>(*endpoints_, clock_, mc, earliest_finish());
    endpoints_->bind(static_cast<ManagerInbox&>(*manager_));
    SF_TRY(start_contractors());
    manager_agent_ = std::make_unique<ManagerAgent>(*manager_, *endpoints_);
    agents_.push_back(manager_agent_.get());
    for (auto& m : machines_) {
      agents_.push_back(m.get());
    }
    if (progress) {
      progress(fmt::format("waiting for {} contractors to be discovered", options_.contractors));
    }
    const auto discovered = [this] {
      return endpoints_->contractors("OP1") >= options_.contractors &&
             endpoints_->bidders("OP1") >= options_.contractors;
    };
    const auto found = [this] { return endpoints_->contractors("OP1") + endpoints_->bidders("OP1"); };
    if (auto st = pump_until(discovered, found, 120s); !st) {
      const auto strand = executor_.hold();
      return Error{Errc::timeout, fmt::format("only {} of {} contractors discovered",
                                              endpoints_->contractors("OP1"), options_.contractors)};
    }
    return {};
  }

  // One negotiation at a time; returns the latencies in microseconds. The next starts once this
  // conversation has ended (INFORM-DONE), so the contractor's report of the work is not measured
  // as part of the next one. It starts from the handler of that end, on whichever thread ran it,
  // as a product starts its next operation and as ddsperf's ping sends its next ping: waking
  // this thread in between would cost every negotiation a thread wake-up.
  Result<std::vector<double>> sequential(std::size_t n) {
    auto chain = std::make_shared<Chain>();
    chain->n = n;
    chain->one_at_a_time = true;
    SF_TRY(run_chain(chain, 1));
    return std::move(chain->latencies);
  }

  // `window` negotiations in flight: each confirmation starts the next; returns negotiations per
  // second.
  Result<double> pipelined(std::size_t n, std::size_t window) {
    auto chain = std::make_shared<Chain>();
    chain->n = n;
    const auto t0 = clock_.now();
    SF_TRY(run_chain(chain, window));
    return static_cast<double>(n) / std::chrono::duration<double>(clock_.now() - t0).count();
  }

  Status drain() {
    return pump_until([&] { return manager_->active() == 0; }, [&] { return manager_->active(); });
  }
  // This process and the contractor processes.
  [[nodiscard]] std::optional<std::chrono::nanoseconds> cpu_time() const {
    std::vector<pid_t> pids{::getpid()};
    for (const auto& c : children_) {
      pids.push_back(c.pid());
    }
    return cpu_time_of(pids);
  }
  const ManagerStats& stats() const { return manager_->stats(); }

 private:
  Status start_contractors() {
    for (std::size_t i = 1; i <= options_.contractors; ++i) {
      const auto name = fmt::format("B{}", i);
      if (!options_.processes) {
        ContractorConfig cfg{name, {{"OP1", 0ns, 1.0}}};
        cfg.capacity = 1'000'000;
        auto m = MachineAgent::create(settings_, cfg, {}, executor_, clock_);
        if (!m) {
          return m.error();
        }
        machines_.push_back(std::move(*m));
        continue;
      }
      auto child = detail::spawn_logged(
          {options_.agent_binary,
           "--log-level",
           "warn",
           "agent",
           "machine",
           "--name",
           name,
           "--ops",
           "OP1",
           "--work-ms",
           "0",
           "--capacity",
           "1000000",
           "--partition",
           settings_.partition,
           "--machining-domain",
           std::to_string(settings_.machining_domain),
           "--conveying-domain",
           std::to_string(settings_.conveying_domain),
           "--interface",
           settings_.network.interface,
           "--lease-ms",
           std::to_string(
               std::chrono::duration_cast<std::chrono::milliseconds>(settings_.liveliness_lease).count()),
           "--spin-us",
           std::to_string(std::chrono::duration_cast<std::chrono::microseconds>(options_.spin).count()),
           "--delivery",
           options_.inline_delivery ? "inline" : "queued",
           "--exit-with-parent"},
          {}, "/dev/null", options_.contractor_scheduling);
      if (!child) {
        return child.error();
      }
      children_.push_back(std::move(*child));
    }
    return {};
  }

  // One phase's chain of negotiations (under the strand). The handlers hold it by shared_ptr: a
  // conversation may outlive its phase (a renegotiation confirms it again during drain()), and
  // then finds the phase over and does nothing.
  struct Chain {
    std::size_t n = 0;
    bool one_at_a_time = false;  // the next starts on INFORM-DONE, otherwise on CONFIRM
    std::size_t started = 0;
    std::set<std::string> confirmed;  // a renegotiated conversation is confirmed again
    std::size_t ended = 0;
    std::vector<double> latencies;  // of the first confirmation of each, in microseconds
    bool over = false;
    [[nodiscard]] bool complete() const { return (one_at_a_time ? ended : confirmed.size()) >= n; }
  };

  // Starts the chain's next negotiation of OP1 (under the strand); a failure to start ends it.
  void start_next(const std::shared_ptr<Chain>& chain) {
    ++chain->started;
    ConversationEvents events;
    events.on_confirmed = [this, chain](const Conversation& c) {
      if (chain->over || !chain->confirmed.insert(c.id).second) {
        return;
      }
      chain->latencies.push_back(
          std::chrono::duration<double, std::micro>(c.confirmed_at - c.started_at).count());
      if (!chain->one_at_a_time && chain->started < chain->n) {
        start_next(chain);
      }
    };
    events.on_done = [this, chain](const Conversation&) {
      if (!chain->over && chain->one_at_a_time && ++chain->ended < chain->n) {
        start_next(chain);
      }
    };
    if (auto id = manager_->negotiate({"bench", "OP1", {}, {}}, std::move(events)); !id && !chain_error_) {
      chain_error_ = id.error();
    }
  }

  // Starts `first` negotiations of the chain, then runs until it is complete or a negotiation
  // could not start. The chain is over when this returns, however it returns.
  Status run_chain(const std::shared_ptr<Chain>& chain, std::size_t first) {
    {
      const auto strand = executor_.hold();
      chain_error_.reset();
      while (chain->started < std::min(first, chain->n)) {
        start_next(chain);
      }
    }
    const auto st = pump_until([&] { return chain->complete() || chain_error_.has_value(); },
                               [&] { return chain->confirmed.size() + chain->ended; });
    const auto strand = executor_.hold();
    chain->over = true;
    if (!st) {
      return st;
    }
    if (chain_error_) {
      return *chain_error_;
    }
    return {};
  }

  // Runs the agents (the manager, in-process contractors) until done() holds, or until
  // progress() (a count) has not moved for `limit`; both are called under the strand.
  // run_agents sleeps until the earliest timer and, with inline delivery, is woken by a message
  // only when it moved a timer earlier or made done() true: no wake-up per negotiation.
  Status pump_until(const std::function<bool()>& done, const std::function<std::size_t()>& progress,
                    std::chrono::seconds limit = 60s) {
    auto end = clock_.now() + limit;
    std::optional<std::size_t> seen;
    run_agents(executor_, clock_, agents_,
               [&] {
                 if (done()) {
                   return true;
                 }
                 if (const auto p = progress(); p != seen) {
                   seen = p;
                   end = clock_.now() + limit;
                 }
                 return clock_.now() > end;
               },
               {options_.inline_delivery});
    const auto strand = executor_.hold();
    if (!done()) {
      return Error{Errc::timeout, fmt::format("no negotiation completed within {} s", limit.count())};
    }
    return {};
  }

  const BenchOptions& options_;
  DdsSettings settings_;
  SteadyClock& clock_ = SteadyClock::instance();
  dds::Executor executor_;
  std::vector<Process> children_;  // stopped last (declared first)
  std::unique_ptr<ProductEndpoints> endpoints_;
  std::unique_ptr<Manager> manager_;
  std::vector<std::unique_ptr<MachineAgent>> machines_;
  std::unique_ptr<Agent> manager_agent_;
  std::vector<Agent*> agents_;        // what pump_until runs
  std::optional<Error> chain_error_;  // under the strand
};

}  // namespace

LatencyStats latency_stats(std::vector<double> samples) {
  LatencyStats s;
  if (samples.empty()) {
    return s;
  }
  std::sort(samples.begin(), samples.end());
  s.samples = samples.size();
  double sum = 0;
  for (const double v : samples) {
    sum += v;
  }
  s.mean_us = sum / static_cast<double>(samples.size());
  const std::span<const double> sorted(samples);
  s.p50_us = bench::percentile_of_sorted(sorted, 0.50);
  s.p90_us = bench::percentile_of_sorted(sorted, 0.90);
  s.p99_us = bench::percentile_of_sorted(sorted, 0.99);
  s.max_us = samples.back();
  return s;
}

Result<BenchResult> run_bench(const BenchOptions& options,
                              const std::function<void(std::string_view)>& progress) {
  if (options.contractors == 0 || options.negotiations == 0 || options.window == 0) {
    return Error{Errc::invalid_argument, "contractors, negotiations and window must be at least 1"};
  }
  if (options.processes && options.agent_binary.empty()) {
    return Error{Errc::invalid_argument, "--processes needs the smartfactory binary to start contractors"};
  }
  BenchResult r;
  r.contractors = options.contractors;
  r.negotiations = options.negotiations;
  r.processes = options.processes;
  r.contractor_scheduling = options.contractor_scheduling;
  r.window = options.window;
  DdsSettings settings = options.dds;
  if (settings.partition == DdsSettings{}.partition) {
    settings.partition = fmt::format("cnp-bench-{}", ::getpid());
  }
  {
    Driver driver{options, settings};
    SF_TRY(driver.setup(progress));
    if (progress) {
      progress(fmt::format("{} contractors ready; {} negotiations one at a time", options.contractors,
                           options.negotiations));
    }
    if (auto warm = driver.sequential(options.warmup); !warm) {
      return warm.error();
    }
    const auto t0 = std::chrono::steady_clock::now();
    const auto cpu0 = driver.cpu_time();
    auto latencies = driver.sequential(options.negotiations);
    if (!latencies) {
      return latencies.error();
    }
    if (const auto cpu1 = driver.cpu_time(); cpu0 && cpu1) {
      r.cpu_us_per_negotiation = microseconds(*cpu1 - *cpu0) / static_cast<double>(options.negotiations);
    }
    r.sequential_per_s = static_cast<double>(options.negotiations) /
                         std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    r.latency = latency_stats(std::move(*latencies));
    if (progress) {
      progress(fmt::format("{} negotiations, {} in flight", options.negotiations, options.window));
    }
    auto rate = driver.pipelined(options.negotiations, options.window);
    if (!rate) {
      return rate.error();
    }
    r.pipelined_per_s = *rate;
    SF_TRY(driver.drain());
    r.renegotiations = driver.stats().renegotiations;
    r.failed = driver.stats().failed;
  }
  if (options.ddsperf) {
    if (progress) {
      progress("ddsperf ping/pong for comparison");
    }
    auto perf = run_ddsperf(options);
    if (perf) {
      const auto& rtt = perf->round_trip;
      r.ddsperf_rtt_p50_us = rtt.p50_us;
      r.ddsperf_rtt_mean_us = rtt.mean_us;
      if (rtt.p50_us > 0) {
        r.ratio_p50 = r.latency.p50_us / rtt.p50_us;
      }
      if (rtt.mean_us && *rtt.mean_us > 0) {
        r.ratio_mean = r.latency.mean_us / *rtt.mean_us;
      }
      r.ddsperf_cpu_us_per_round_trip = perf->cpu_us_per_round_trip;
      if (r.cpu_us_per_negotiation && perf->cpu_us_per_round_trip && *perf->cpu_us_per_round_trip > 0) {
        r.cpu_ratio = *r.cpu_us_per_negotiation / *perf->cpu_us_per_round_trip;
      }
    } else if (progress) {
      progress(fmt::format("ddsperf skipped: {}", perf.error().describe()));
    }
  }
  return r;
}

}  // namespace sf::negotiation
