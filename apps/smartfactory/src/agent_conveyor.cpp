// `smartfactory agent conveyor`: a conveyor that answers transport REQUESTs with its segment
// (paper §IV.B, ConveyingDomain).
#include "agent_common.hpp"

#include <iostream>
#include <memory>

#include <fmt/format.h>

#include "sf/core/clock.hpp"

namespace sf::app::agents {
namespace {

using namespace std::chrono_literals;

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

}  // namespace

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

}  // namespace sf::app::agents
