// `smartfactory agent machine|conveyor|product` and `smartfactory cnp bench|layout`: the
// shop-floor entities of the paper (§IV.B) as processes that negotiate over DDS with the Contract
// Net Protocol, and the tools around them. One file per command (agent_*.cpp, cnp_*.cpp); they
// parse options and print, the negotiation module does the work.
#include "agent_common.hpp"

namespace sf::app {

void register_agent(CLI::App& app, CommandResult& result) {
  auto* group = app.add_subcommand(
      "agent", "Shop-floor agents negotiating over DDS with the Contract Net Protocol (paper section IV.B)");
  group->require_subcommand(1);
  group->footer(
      "Machines and conveyors run until signalled; products exit when their operations are done.\n"
      "Agents meet in DDS domains 10 (machining) and 11 (conveying) on loopback by default.");
  agents::register_machine(*group, result);
  agents::register_conveyor(*group, result);
  agents::register_product(*group, result);
}

void register_cnp(CLI::App& app, CommandResult& result) {
  auto* group = app.add_subcommand("cnp", "Contract Net Protocol tools");
  group->require_subcommand(1);
  agents::register_bench(*group, result);
  agents::register_layout(*group, result);
}

}  // namespace sf::app
