// What the agent commands (`agent machine|conveyor|product`) and the cnp tools (`cnp bench|layout`)
// share: the DDS options and their settings, event output (JSON lines or text), the entity layout
// and the run loop until SIGINT/SIGTERM. Private to apps/smartfactory.
#pragma once

#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "commands.hpp"
#include "sf/dds/executor.hpp"
#include "sf/dds/participant.hpp"
#include "sf/negotiation/agents.hpp"
#include "sf/negotiation/dds_transport.hpp"

namespace sf::app::agents {

namespace cnp = sf::negotiation;
using nlohmann::json;

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

void add_dds_options(CLI::App& cmd, DdsCliOptions& o);
void add_layout_option(CLI::App& cmd, DdsCliOptions& o);
cnp::DdsSettings dds_settings(const DdsCliOptions& o);
cnp::RunOptions run_options(const DdsCliOptions& o);

// One line per event, stamped with UTC nanoseconds (comparable across processes on a host);
// flushed, so a test reading a pipe (or a process that is killed right after) loses nothing.
void emit(json event);
void say(const std::string& line);
void print_layout(const std::vector<const dds::Participant*>& participants, bool as_json);

// With --exit-with-parent: SIGTERM when the parent dies (Linux PR_SET_PDEATHSIG). Called first
// thing, so that the parent's death is noticed from then on.
void exit_with_parent(const DdsCliOptions& o);
int run_until_stopped(dds::Executor& ex, cnp::Agent& agent, const DdsCliOptions& o);

// The subcommands, one file each.
void register_machine(CLI::App& group, CommandResult& result);
void register_conveyor(CLI::App& group, CommandResult& result);
void register_product(CLI::App& group, CommandResult& result);
void register_bench(CLI::App& group, CommandResult& result);
void register_layout(CLI::App& group, CommandResult& result);

}  // namespace sf::app::agents
