// `smartfactory machine --config FILE`: the smart robot's IPC (paper §VII.A), the process that
// masters the robot's own EtherCAT segment at 1 kHz and negotiates its work over DDS. This file
// parses options and prints; the factory module (machine_process.hpp) does the work.
#include <chrono>
#include <iostream>
#include <memory>
#include <string>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "commands.hpp"
#include "controller_report.hpp"
#include "sf/core/clock.hpp"
#include "sf/factory/machine_process.hpp"

namespace sf::app {
namespace {

using nlohmann::json;
namespace fy = sf::factory;

constexpr const char* kMachineHelp =
    "The smart robot's IPC (the paper's smart controller, §VII.A): it masters the robot's own\n"
    "EtherCAT segment (8 CiA 402 servo axes, 32 DI, 32 DO) in cyclic synchronous position at\n"
    "1 kHz, interpolating blended Cartesian paths on the master, runs the robot as a PackML\n"
    "unit (Reset homes it) and takes part in the Contract Net over DDS: bids from the planned\n"
    "cycle time, its queue and its dispensers; awarded loads done on the arm; INFORM-DONE or\n"
    "FAILURE to the product. Axis faults abort it, a lost segment stops it and it resets by\n"
    "itself once the segment is back. It prints a status line whenever the PackML state, the\n"
    "job or the queue changes (JSON lines with --json). A configuration error names\n"
    "FILE:LINE:COLUMN and nothing starts (exit status 2).";

constexpr const char* kConfigHelp =
    "machine.yaml (the default line's: configs/scara-robot-1.yaml; docs/shop-floor.md):\n"
    "  machine: scara-robot-1      # the layout's smart robot\n"
    "  layout: ../layouts/prototype-line.yaml   # default: the built-in layout\n"
    "  start: execute              # stopped (default): wait for an operator's Reset, Start\n"
    "  ethercat: {link: udp:127.0.0.1:34980, cycle_us: 1000}   # or link: <interface>\n"
    "  dds: {machining_domain: 10, interface: lo, partition: smartfactory}";

struct MachineOptions {
  std::string config;
  bool json = false;
  bool check = false;
  double status_interval_s = 5;
  double duration_s = 0;
};

double us(std::chrono::nanoseconds d) {
  return std::chrono::duration<double, std::micro>(d).count();
}

void print_report(const fy::MachineReport& r, bool as_json) {
  const auto& s = r.controller;
  if (as_json) {
    auto j = controller_status_json(r.identification.name, s, r.contract_net);
    j["link"] = r.link;
    j["cycles"] = r.cycles;
    j["realtime"] = r.realtime;
    j["lateness_us"] = {
        {"p50", us(r.lateness_p50)}, {"p99", us(r.lateness_p99)}, {"max", us(r.lateness_max)}};
    std::cout << j.dump() << std::endl;
    return;
  }
  std::cout << fmt::format("{}; {} cycles, lateness p50/p99/max {:.0f}/{:.0f}/{:.0f} µs{}{}{}\n",
                           controller_status_text(r.identification.name, s, r.contract_net), r.cycles,
                           us(r.lateness_p50), us(r.lateness_p99), us(r.lateness_max),
                           r.realtime ? " (SCHED_FIFO)" : "", s.fault.empty() ? "" : "; fault: ", s.fault)
            << std::flush;
}

void print_ready(const fy::MachineProcess& p, bool as_json) {
  const fy::MachineConfig& c = p.setup().config;
  const auto r = p.report();
  if (as_json) {
    std::cout << json{{"event", "ready"},
                      {"machine", c.controller.machine},
                      {"link", c.ethercat.link},
                      {"cycle_us", c.ethercat.cycle.count()},
                      {"serial_number", r.identification.serial_number},
                      {"opcua", r.opcua_endpoint},
                      {"opcua_security", r.opcua_security},
                      {"machining_domain", c.controller.dds.machining_domain}}
                     .dump()
              << std::endl;
    return;
  }
  std::cout << fmt::format(
                   "machine {} ({} {}, serial {}): EtherCAT {} every {} µs; DDS domain {} on {}\n"
                   "  OPC UA {} ({})\n",
                   c.controller.machine, r.identification.manufacturer, r.identification.model,
                   r.identification.serial_number, c.ethercat.link, c.ethercat.cycle.count(),
                   c.controller.dds.machining_domain, c.controller.dds.interface, r.opcua_endpoint,
                   r.opcua_security)
            << std::flush;
}

std::chrono::nanoseconds seconds(double s) {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::duration<double>(s));
}

int run_machine(const MachineOptions& o) {
  auto setup = fy::load_machine_config(o.config);
  if (!setup) {
    std::cerr << "machine: " << setup.error().message << "\n";
    return kExitUsage;
  }
  if (o.check) {
    std::cout << fmt::format("{}: machine {} is valid\n", o.config, setup->config.controller.machine);
    return kExitOk;
  }
  auto& clock = SteadyClock::instance();
  install_stop_signals();
  auto process = fy::MachineProcess::create(std::move(*setup), clock);
  if (!process) {
    std::cerr << "machine: " << process.error().describe() << "\n";
    return kExitFailure;
  }
  print_ready(**process, o.json);
  const auto end = o.duration_s > 0 ? clock.now() + seconds(o.duration_s) : Clock::time_point::max();
  (*process)->run([&] { return stop_requested() || clock.now() >= end; },
                  [&](const fy::MachineReport& r) { print_report(r, o.json); }, seconds(o.status_interval_s));
  return kExitOk;
}

}  // namespace

void register_machine(CLI::App& app, CommandResult& result) {
  auto o = std::make_shared<MachineOptions>();
  auto* cmd = app.add_subcommand(
      "machine",
      "The smart robot's IPC: its EtherCAT segment at 1 kHz, PackML, and its part in the Contract Net");
  cmd->description(kMachineHelp);
  cmd->add_option("--config", o->config, "The machine's YAML file (machine, EtherCAT link, DDS)")->required();
  cmd->add_flag("--json", o->json, "Status as JSON lines on stdout (events ready, status)");
  cmd->add_flag("--check", o->check, "Only check the configuration against its layout, then exit");
  cmd->add_option("--status-interval", o->status_interval_s,
                  "Seconds between status lines when nothing changes")
      ->capture_default_str();
  cmd->add_option("--duration", o->duration_s, "Stop after this many seconds (0 = until SIGINT/SIGTERM)")
      ->capture_default_str();
  cmd->footer(kConfigHelp);
  cmd->callback([o, &result] { result.exit_code = run_machine(*o); });
}

}  // namespace sf::app
