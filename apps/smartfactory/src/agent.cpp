// `smartfactory agent machine|conveyor|product` and `smartfactory cnp bench`:
// the shop-floor entities of the paper (§IV.B) as processes that negotiate
// over DDS with the Contract Net Protocol, and the negotiation benchmark.
// Everything here parses options and prints; the negotiation module does the work.
#include <sys/prctl.h>
#include <unistd.h>

#include <array>
#include <csignal>
#include <cstdio>
#include <iostream>
#include <memory>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <nlohmann/json.hpp>

#include "commands.hpp"
#include "sf/bench/cnp.hpp"
#include "sf/core/clock.hpp"
#include "sf/core/log.hpp"
#include "sf/dds/introspection.hpp"
#include "sf/negotiation/agents.hpp"

namespace sf::app {
namespace {

namespace cnp = sf::negotiation;
using nlohmann::json;
using namespace std::chrono_literals;

// --- options shared by every agent ----------------------------------------------

struct DdsCliOptions {
  unsigned machining_domain = 10;
  unsigned conveying_domain = 11;
  std::string partition = "smartfactory";
  std::string interface = "lo";
  unsigned lease_ms = 1000;
  unsigned spin_us = 0;
  std::string delivery = "inline";
  bool exit_with_parent = false;
  bool json = false;
  bool layout = false;
};

void add_dds_options(CLI::App& cmd, DdsCliOptions& o) {
  cmd.add_option("--machining-domain", o.machining_domain, "DDS domain id of the MachiningDomain")
      ->check(CLI::Range(0U, 232U))
      ->capture_default_str();
  cmd.add_option("--conveying-domain", o.conveying_domain, "DDS domain id of the ConveyingDomain")
      ->check(CLI::Range(0U, 232U))
      ->capture_default_str();
  cmd.add_option("--partition", o.partition,
                 "DDS partition: only agents in the same partition negotiate (one per plant or test run)")
      ->capture_default_str();
  cmd.add_option("--interface", o.interface,
                 "Network interface: 'lo' = loopback only (unicast discovery, no multicast), "
                 "otherwise a NIC name or address with multicast discovery")
      ->capture_default_str();
  cmd.add_option("--lease-ms", o.lease_ms,
                 "Liveliness lease of a machine's BID writers: a machine silent this long is presumed dead")
      ->check(CLI::Range(50U, 600'000U))
      ->capture_default_str();
  cmd.add_option("--spin-us", o.spin_us,
                 "Poll for incoming messages this long before sleeping: lower latency for more CPU")
      ->capture_default_str();
  cmd.add_option("--delivery", o.delivery,
                 "Where messages are handled: 'inline' on the DDS thread that received them (one thread "
                 "wake-up less per message), 'queued' on the agent's own thread")
      ->check(CLI::IsMember({"inline", "queued"}))
      ->capture_default_str();
  cmd.add_flag("--exit-with-parent", o.exit_with_parent,
               "Stop (as on SIGTERM) when the process that started this one dies, e.g. a benchmark "
               "killed before it could stop its agents");
  cmd.add_flag("--json", o.json, "Print events (or the result) as JSON on stdout");
}

void add_layout_option(CLI::App& cmd, DdsCliOptions& o) {
  cmd.add_flag("--layout", o.layout,
               "Print this agent's DDS entity layout (readers, writers, topics) at start");
}

cnp::DdsSettings dds_settings(const DdsCliOptions& o) {
  cnp::DdsSettings s;
  s.machining_domain = o.machining_domain;
  s.conveying_domain = o.conveying_domain;
  s.partition = o.partition;
  s.network = o.interface == "lo" ? dds::loopback_network() : dds::interface_network(o.interface);
  s.liveliness_lease = std::chrono::milliseconds{o.lease_ms};
  return s;
}

// One line per event, stamped with UTC nanoseconds (comparable across
// processes on a host); flushed, so a test reading a pipe (or a process that
// is killed right after) loses nothing.
void emit(json event) {
  event["t"] = std::chrono::duration_cast<std::chrono::nanoseconds>(
                   SteadyClock::instance().utc_now().time_since_epoch())
                   .count();
  std::cout << event.dump() << '\n' << std::flush;
}

void say(const std::string& line) {
  std::cout << line << '\n' << std::flush;
}

void print_layout(const std::vector<const dds::Participant*>& participants, bool as_json) {
  json all = json::array();
  for (const auto* p : participants) {
    auto layout = dds::inspect(*p);
    if (!layout) {
      std::cerr << "layout: " << layout.error().describe() << "\n";
      continue;
    }
    all.push_back(json::parse(dds::to_json(*layout)));
  }
  if (as_json) {
    emit(json{{"event", "layout"}, {"participants", all}});
    return;
  }
  for (const auto& p : all) {
    say(fmt::format("layout {} (domain {}): {} readers, {} writers", p["participant"].get<std::string>(),
                    p["domain"].get<unsigned>(), p["readers"].size(), p["writers"].size()));
  }
}

// The kernel sends SIGTERM when the parent dies (Linux PR_SET_PDEATHSIG). Called first thing,
// so that the parent's death is noticed from then on (it may not be stopped by then yet).
void exit_with_parent(const DdsCliOptions& o) {
  if (o.exit_with_parent) {
    const pid_t parent = getppid();
    prctl(PR_SET_PDEATHSIG, SIGTERM);
    if (getppid() != parent) {  // died in between
      raise(SIGTERM);
    }
  }
}

cnp::RunOptions run_options(const DdsCliOptions& o) {
  return cnp::RunOptions{o.delivery == "inline"};
}

int run_until_stopped(dds::Executor& ex, cnp::Agent& agent, const DdsCliOptions& o) {
  install_stop_signals();
  cnp::run_agents(
      ex, SteadyClock::instance(), {&agent}, [] { return stop_requested(); }, run_options(o));
  return kExitOk;
}

// --- agent machine -----------------------------------------------------------------

struct MachineCliOptions {
  DdsCliOptions dds;
  std::string name;
  std::string ops;
  double speed = 1.0;
  unsigned work_ms = 100;
  unsigned jitter_ms = 0;
  unsigned capacity = 64;
  double fail_rate = 0.0;
  std::uint64_t seed = 1;
  std::string kill_after;
};

// "--kill-after bid:N|award:N|confirm:N": a test hook that kills this process
// (SIGKILL, no goodbye on the wire) right after its Nth bid, Nth award received
// (before confirming) or Nth confirmation (while working).
struct KillHook {
  std::string what;
  unsigned after = 0;
  unsigned seen = 0;
  void count(std::string_view event) {
    if (after > 0 && event == what && ++seen == after) {
      emit(json{{"event", "killed"}, {"after", what}, {"count", seen}});
      std::raise(SIGKILL);
    }
  }
};

Result<KillHook> parse_kill_hook(const std::string& spec) {
  if (spec.empty()) {
    return KillHook{};
  }
  const auto colon = spec.find(':');
  const auto what = spec.substr(0, colon);
  if (colon == std::string::npos || (what != "bid" && what != "award" && what != "confirm")) {
    return Error{Errc::invalid_argument, "--kill-after: expected bid:N, award:N or confirm:N"};
  }
  try {
    const auto n = std::stoul(spec.substr(colon + 1));
    return KillHook{what, static_cast<unsigned>(n), 0};
  } catch (const std::exception&) {
    return Error{Errc::invalid_argument, "--kill-after: N must be a number"};
  }
}

json job_event(std::string_view event, const std::string& machine, const cnp::Job& j) {
  return json{{"event", event},       {"machine", machine},       {"conversation", j.conversation},
              {"product", j.product}, {"operation", j.operation}, {"award", j.award_id}};
}

cnp::ContractorEvents machine_events(const MachineCliOptions& o, std::shared_ptr<KillHook> hook) {
  cnp::ContractorEvents ev;
  const auto name = o.name;
  const bool as_json = o.dds.json;
  ev.on_bid = [=](const cnp::Announce& a) {
    if (as_json) {
      emit(json{{"event", "bid"}, {"machine", name}, {"conversation", a.conversation}, {"round", a.round}});
    }
    hook->count("bid");
  };
  ev.on_awarded = [=](const cnp::ManagerMessage&) { hook->count("award"); };
  ev.on_confirmed = [=](const cnp::Job& j) {
    if (as_json) {
      emit(job_event("confirmed", name, j));
    }
    hook->count("confirm");
  };
  ev.on_work_started = [=](const cnp::Job& j) {
    as_json ? emit(job_event("start", name, j))
            : say(fmt::format("{}: working {} for {}", name, j.operation, j.product));
  };
  ev.on_work_finished = [=](const cnp::Job& j, bool ok) {
    if (as_json) {
      emit(job_event(ok ? "done" : "failure", name, j));
    }
  };
  ev.on_work_aborted = [=](const cnp::Job& j, const std::string& why) {
    if (as_json) {
      auto e = job_event("abort", name, j);
      e["reason"] = why;
      emit(e);
    }
  };
  return ev;
}

int run_machine(const MachineCliOptions& o) {
  exit_with_parent(o.dds);
  auto ops = cnp::parse_operations(o.ops);
  auto hook = parse_kill_hook(o.kill_after);
  if (!ops || !hook) {
    std::cerr << "agent machine: " << (!ops ? ops.error() : hook.error()).message << "\n";
    return kExitUsage;
  }
  cnp::ContractorConfig cfg{o.name, {}};
  for (const auto& op : *ops) {
    cfg.skills.push_back({op, std::chrono::milliseconds{o.work_ms}, 1.0});
  }
  cfg.speed = o.speed;
  cfg.capacity = o.capacity;
  cfg.jitter = std::chrono::milliseconds{o.jitter_ms};
  cfg.failure_probability = o.fail_rate;
  cfg.seed = o.seed;
  dds::Executor ex;
  ex.set_spin(std::chrono::microseconds{o.dds.spin_us});
  auto agent = cnp::MachineAgent::create(dds_settings(o.dds), cfg,
                                         machine_events(o, std::make_shared<KillHook>(*hook)), ex,
                                         SteadyClock::instance());
  if (!agent) {
    std::cerr << "agent machine: " << agent.error().describe() << "\n";
    return agent.error().code == Errc::invalid_argument ? kExitUsage : kExitFailure;
  }
  if (o.dds.layout) {
    print_layout({&(*agent)->endpoints().participant()}, o.dds.json);
  }
  o.dds.json ? emit(json{{"event", "ready"}, {"machine", o.name}, {"ops", *ops}})
             : say(fmt::format("machine {} ready for {}", o.name, o.ops));
  return run_until_stopped(ex, **agent, o.dds);
}

void register_machine(CLI::App& group, CommandResult& result) {
  auto o = std::make_shared<MachineCliOptions>();
  auto* cmd = group.add_subcommand(
      "machine", "A machine (contractor): bids on the operations it can do, confirms awards, works them");
  cmd->add_option("--name", o->name, "Machine name, unique in the partition (e.g. M1)")->required();
  cmd->add_option("--ops", o->ops, "Operation types it performs, comma-separated (e.g. OP1,OP2)")->required();
  cmd->add_option("--speed", o->speed, "Speed factor: an operation takes work-ms / speed")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  cmd->add_option("--work-ms", o->work_ms, "Duration of one operation at speed 1, in milliseconds")
      ->capture_default_str();
  cmd->add_option("--jitter-ms", o->jitter_ms, "Each operation takes up to this much longer, at random")
      ->capture_default_str();
  cmd->add_option("--capacity", o->capacity, "Jobs queued or running at most; beyond, calls are declined")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  cmd->add_option("--fail-rate", o->fail_rate, "Probability (0..1) that an operation ends in FAILURE")
      ->check(CLI::Range(0.0, 1.0));
  cmd->add_option("--seed", o->seed, "Random seed for jitter and failures");
  cmd->add_option("--kill-after", o->kill_after,
                  "Test hook: SIGKILL this process after its Nth bid, award or confirmation (bid:N, award:N, "
                  "confirm:N)");
  add_dds_options(*cmd, o->dds);
  add_layout_option(*cmd, o->dds);
  cmd->footer(
      "Runs until SIGINT/SIGTERM. Example:\n  smartfactory agent machine --name M1 --ops OP1,OP2 --speed 2");
  cmd->callback([o, &result] { result.exit_code = run_machine(*o); });
}

// --- agent conveyor ----------------------------------------------------------------

struct ConveyorCliOptions {
  DdsCliOptions dds;
  std::string name;
  std::string from;
  std::string to;
  unsigned transit_ms = 1000;
};

int run_conveyor(const ConveyorCliOptions& o) {
  exit_with_parent(o.dds);
  dds::Executor ex;
  ex.set_spin(std::chrono::microseconds{o.dds.spin_us});
  auto agent = cnp::ConveyorAgent::create(dds_settings(o.dds),
                                          {o.name, o.from, o.to, std::chrono::milliseconds{o.transit_ms}}, ex,
                                          SteadyClock::instance());
  if (!agent) {
    std::cerr << "agent conveyor: " << agent.error().describe() << "\n";
    return agent.error().code == Errc::invalid_argument ? kExitUsage : kExitFailure;
  }
  if (o.dds.layout) {
    print_layout({&(*agent)->endpoints().participant()}, o.dds.json);
  }
  o.dds.json ? emit(json{{"event", "ready"}, {"conveyor", o.name}, {"from", o.from}, {"to", o.to}})
             : say(fmt::format("conveyor {} ready: {} -> {}", o.name, o.from, o.to));
  return run_until_stopped(ex, **agent, o.dds);
}

void register_conveyor(CLI::App& group, CommandResult& result) {
  auto o = std::make_shared<ConveyorCliOptions>();
  auto* cmd = group.add_subcommand(
      "conveyor", "A conveyor: answers every transport REQUEST with its segment (from, to) and transit time");
  cmd->add_option("--name", o->name, "Conveyor name, unique in the partition (e.g. C1)")->required();
  cmd->add_option("--from", o->from, "Where the belt starts: a machine name or a place such as Input")
      ->required();
  cmd->add_option("--to", o->to, "Where the belt ends: a machine name or a place such as Output")->required();
  cmd->add_option("--transit-ms", o->transit_ms, "Time to carry a product from one end to the other")
      ->capture_default_str();
  add_dds_options(*cmd, o->dds);
  add_layout_option(*cmd, o->dds);
  cmd->footer(
      "Runs until SIGINT/SIGTERM. Example:\n  smartfactory agent conveyor --name C1 --from Input --to M1");
  cmd->callback([o, &result] { result.exit_code = run_conveyor(*o); });
}

// --- agent product -----------------------------------------------------------------

struct ProductCliOptions {
  DdsCliOptions dds;
  std::string name;
  std::string ops;
  unsigned count = 1;
  unsigned parallel = 0;
  std::string start = "Input";
  bool no_route = false;
  std::string policy = "earliest-finish";
  std::vector<std::string> direct;
  unsigned bid_ms = 500;
  unsigned confirm_ms = 500;
  unsigned max_rounds = 10;
  unsigned discovery_ms = 5000;
  double timeout_s = 0;
};

json route_json(const cnp::Route& r) {
  json segments = json::array();
  for (const auto& s : r.segments) {
    segments.push_back({{"conveyor", s.conveyor}, {"from", s.from}, {"to", s.to}});
  }
  return segments;
}

cnp::ProductEvents product_events(bool as_json) {
  cnp::ProductEvents ev;
  ev.on_award = [as_json](const std::string& p, const cnp::Conversation& c) {
    const auto us = std::chrono::duration<double, std::micro>(c.confirmed_at - c.started_at).count();
    as_json ? emit(json{{"event", "award"},
                        {"product", p},
                        {"operation", c.operation},
                        {"conversation", c.id},
                        {"contractor", c.contractor},
                        {"award", c.last_award},
                        {"round", c.round},
                        {"renegotiations", c.renegotiations},
                        {"latency_us", us}})
            : say(fmt::format("{}: {} awarded to {} (round {}, award {}, {:.3f} ms)", p, c.operation,
                              c.contractor, c.round, c.last_award, us / 1000.0));
  };
  ev.on_route = [as_json](const std::string& p, const cnp::Route& r) {
    as_json ? emit(json{{"event", "route"},
                        {"product", p},
                        {"from", r.from},
                        {"to", r.to},
                        {"segments", route_json(r)},
                        {"eta_ms", std::chrono::duration<double, std::milli>(r.eta()).count()}})
            : say(fmt::format("{}: route {}", p, r.describe()));
  };
  ev.on_step_done = [as_json](const std::string& p, const cnp::Step& s) {
    if (as_json) {
      emit(json{{"event", "done"},
                {"product", p},
                {"operation", s.operation},
                {"conversation", s.conversation},
                {"contractor", s.contractor}});
    }
  };
  ev.on_finished = [as_json](const std::string& p, bool ok, const std::string& why) {
    as_json ? emit(json{{"event", "finished"}, {"product", p}, {"ok", ok}, {"error", why}})
            : say(ok ? fmt::format("{}: finished", p) : fmt::format("{}: FAILED: {}", p, why));
  };
  return ev;
}

Result<cnp::ProductAgentConfig> product_config(const ProductCliOptions& o) {
  auto ops = cnp::parse_operations(o.ops);
  if (!ops) {
    return ops.error();
  }
  auto policy = cnp::policy_by_name(o.policy);
  if (!policy) {
    return policy.error();
  }
  cnp::ProductAgentConfig c;
  c.name = o.name;
  c.operations = std::move(*ops);
  c.count = o.count;
  c.parallel = o.parallel;
  c.start = o.start;
  c.route = !o.no_route;
  c.policy = std::move(*policy);
  c.manager.bid_window = std::chrono::milliseconds{o.bid_ms};
  c.manager.confirm_window = std::chrono::milliseconds{o.confirm_ms};
  c.manager.confirm_grace = std::chrono::milliseconds{o.confirm_ms / 2};
  c.manager.max_rounds = o.max_rounds;
  c.discovery_timeout = std::chrono::milliseconds{o.discovery_ms};
  for (const auto& d : o.direct) {
    const auto eq = d.find('=');
    if (eq == std::string::npos || eq == 0 || eq + 1 == d.size()) {
      return Error{Errc::invalid_argument, fmt::format("--direct '{}': expected OP=MACHINE", d)};
    }
    c.directed[d.substr(0, eq)] = d.substr(eq + 1);
  }
  return c;
}

int run_product(const ProductCliOptions& o) {
  exit_with_parent(o.dds);
  auto cfg = product_config(o);
  if (!cfg) {
    std::cerr << "agent product: " << cfg.error().message << "\n";
    return kExitUsage;
  }
  dds::Executor ex;
  ex.set_spin(std::chrono::microseconds{o.dds.spin_us});
  auto& clock = SteadyClock::instance();
  auto agent = cnp::ProductAgent::create(dds_settings(o.dds), *cfg, product_events(o.dds.json), ex, clock);
  if (!agent) {
    std::cerr << "agent product: " << agent.error().describe() << "\n";
    return agent.error().code == Errc::invalid_argument ? kExitUsage : kExitFailure;
  }
  if (o.dds.layout) {
    std::vector<const dds::Participant*> parts{&(*agent)->endpoints().machining()};
    if (const auto* c = (*agent)->endpoints().conveying()) {
      parts.push_back(c);
    }
    print_layout(parts, o.dds.json);
  }
  install_stop_signals();
  const auto deadline = o.timeout_s > 0 ? clock.now() + std::chrono::duration_cast<std::chrono::nanoseconds>(
                                                            std::chrono::duration<double>(o.timeout_s))
                                        : Clock::time_point::max();
  cnp::run_agents(
      ex, clock, {agent->get()}, [&] { return stop_requested() || clock.now() > deadline; },
      run_options(o.dds));
  const auto& a = **agent;
  if (o.dds.json) {
    emit(json{{"event", "summary"},
              {"succeeded", a.succeeded()},
              {"failed", a.failed()},
              {"unfinished", a.products().size() - a.succeeded() - a.failed()}});
  } else {
    say(fmt::format("{} of {} products finished, {} failed", a.succeeded(), a.products().size(), a.failed()));
  }
  return a.succeeded() == a.products().size() ? kExitOk : kExitFailure;
}

void register_product(CLI::App& group, CommandResult& result) {
  auto o = std::make_shared<ProductCliOptions>();
  auto* cmd = group.add_subcommand(
      "product",
      "A product (manager): negotiates each operation with the machines and a conveyor route to the winner; "
      "prints each award and exits when done");
  cmd->add_option("--name", o->name, "Product name (with --count K: NAME-1..NAME-K)")->required();
  cmd->add_option("--ops", o->ops, "Operations it needs, in order, comma-separated (e.g. OP1,OP2)")
      ->required();
  cmd->add_option("--count", o->count, "How many products of this kind this process manages")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  cmd->add_option("--parallel", o->parallel, "Products in progress at once (0 = all)")->capture_default_str();
  cmd->add_option("--start", o->start, "Where products enter the conveyor graph")->capture_default_str();
  cmd->add_flag("--no-route", o->no_route, "Negotiate operations only, no conveyor routes");
  cmd->add_option("--policy", o->policy, "Bid selection: earliest-finish, lowest-cost or load-balance")
      ->capture_default_str();
  cmd->add_option("--direct", o->direct,
                  "OP=MACHINE: award OP to MACHINE without a call for bids (DIRECTEDAWARD); repeatable");
  cmd->add_option("--bid-ms", o->bid_ms,
                  "Bid deadline after an ANNOUNCE (earlier once every machine answered)")
      ->capture_default_str();
  cmd->add_option("--confirm-ms", o->confirm_ms, "Time an awarded machine has to CONFIRM")
      ->capture_default_str();
  cmd->add_option("--max-rounds", o->max_rounds,
                  "Announcements per operation before giving up (0 = no limit)")
      ->capture_default_str();
  cmd->add_option("--discovery-ms", o->discovery_ms,
                  "Wait up to this long for machines (and conveyors) to be discovered before announcing")
      ->capture_default_str();
  cmd->add_option("--timeout", o->timeout_s, "Give up after this many seconds (0 = never)");
  add_dds_options(*cmd, o->dds);
  add_layout_option(*cmd, o->dds);
  cmd->footer(
      "Exit status 0 when every product got all its operations done. Example:\n"
      "  smartfactory agent product --name P1 --ops OP1,OP2 --count 3");
  cmd->callback([o, &result] { result.exit_code = run_product(*o); });
}

// --- cnp bench ---------------------------------------------------------------------

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

// --- cnp layout --------------------------------------------------------------------

struct LayoutCliOptions {
  DdsCliOptions dds;
  unsigned settle_ms = 1500;
};

int run_layout(const LayoutCliOptions& o) {
  const auto settings = dds_settings(o.dds);
  auto xml = dds::cyclone_config_xml(settings.network);
  if (!xml) {
    std::cerr << "cnp layout: " << xml.error().describe() << "\n";
    return kExitUsage;
  }
  json out = json::array();
  for (const auto domain : {settings.machining_domain, settings.conveying_domain}) {
    auto observer = dds::Participant::create(domain, {*xml, "observer", settings.partition});
    if (!observer) {
      std::cerr << "cnp layout: " << observer.error().describe() << "\n";
      return kExitFailure;
    }
    auto seen = dds::discover(*observer, SteadyClock::instance(), std::chrono::milliseconds{o.settle_ms},
                              settings.partition);
    if (!seen) {
      std::cerr << "cnp layout: " << seen.error().describe() << "\n";
      return kExitFailure;
    }
    for (const auto& layout : *seen) {
      out.push_back(json::parse(dds::to_json(layout)));
    }
  }
  if (o.dds.json) {
    std::cout << out.dump() << "\n";
    return kExitOk;
  }
  for (const auto& p : out) {
    std::vector<std::string> readers;
    std::vector<std::string> writers;
    for (const auto& r : p["readers"]) {
      readers.push_back(r["topic"].get<std::string>());
    }
    for (const auto& w : p["writers"]) {
      writers.push_back(w["topic"].get<std::string>());
    }
    say(fmt::format("{} (domain {}): readers [{}] writers [{}]", p["participant"].get<std::string>(),
                    p["domain"].get<unsigned>(), fmt::join(readers, " "), fmt::join(writers, " ")));
  }
  return kExitOk;
}

}  // namespace

void register_agent(CLI::App& app, CommandResult& result) {
  auto* group = app.add_subcommand(
      "agent", "Shop-floor agents negotiating over DDS with the Contract Net Protocol (paper section IV.B)");
  group->require_subcommand(1);
  group->footer(
      "Machines and conveyors run until signalled; products exit when their operations are done.\n"
      "Agents meet in DDS domains 10 (machining) and 11 (conveying) on loopback by default.");
  register_machine(*group, result);
  register_conveyor(*group, result);
  register_product(*group, result);
}

void register_cnp(CLI::App& app, CommandResult& result) {
  auto* group = app.add_subcommand("cnp", "Contract Net Protocol tools");
  group->require_subcommand(1);
  auto o = std::make_shared<BenchCliOptions>();
  auto* cmd = group->add_subcommand(
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

  auto l = std::make_shared<LayoutCliOptions>();
  auto* layout = group->add_subcommand(
      "layout",
      "List every agent in both domains with its DDS readers and writers, as discovered through the "
      "built-in topics (DCPSParticipant, DCPSPublication, DCPSSubscription)");
  layout->add_option("--settle-ms", l->settle_ms, "How long to listen for discovery before printing")
      ->capture_default_str();
  add_dds_options(*layout, l->dds);
  layout->callback([l, &result] { result.exit_code = run_layout(*l); });
}

}  // namespace sf::app
