// `smartfactory agent machine`: a machine (contractor) that bids on the operations it can do,
// confirms awards and works them (paper §IV.B, MachiningDomain).
#include "agent_common.hpp"

#include <csignal>
#include <iostream>
#include <memory>
#include <string>
#include <string_view>

#include <fmt/format.h>

#include "sf/core/clock.hpp"

namespace sf::app::agents {
namespace {

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
  std::string kill_after;  // test builds only (SF_TEST_HOOKS)
};

#ifdef SF_TEST_HOOKS
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
#else
// Release builds have no test hooks: nothing is ever killed.
struct KillHook {
  void count(std::string_view /*event*/) {}
};
#endif

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
#ifdef SF_TEST_HOOKS
  auto hook = parse_kill_hook(o.kill_after);
#else
  Result<KillHook> hook = KillHook{};
#endif
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

}  // namespace

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
#ifdef SF_TEST_HOOKS
  cmd->add_option("--kill-after", o->kill_after,
                  "Test hook: SIGKILL this process after its Nth bid, award or confirmation (bid:N, award:N, "
                  "confirm:N)");
#endif
  add_dds_options(*cmd, o->dds);
  add_layout_option(*cmd, o->dds);
  cmd->footer(
      "Runs until SIGINT/SIGTERM. Example:\n  smartfactory agent machine --name M1 --ops OP1,OP2 --speed 2");
  cmd->callback([o, &result] { result.exit_code = run_machine(*o); });
}

}  // namespace sf::app::agents
