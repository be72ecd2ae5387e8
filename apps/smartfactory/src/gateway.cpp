// `smartfactory gateway --config FILE`: a legacy machine's gateway (paper §VII.B), the process
// next to a closed PLC that speaks its Modbus TCP and negotiates on its behalf over DDS. This
// file parses options and prints; the factory module (gateway_process.hpp) does the work.
#include <chrono>
#include <iostream>
#include <memory>
#include <string>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "commands.hpp"
#include "controller_report.hpp"
#include "sf/core/clock.hpp"
#include "sf/factory/conveying.hpp"
#include "sf/factory/gateway_process.hpp"

namespace sf::app {
namespace {

using nlohmann::json;
namespace fy = sf::factory;

constexpr const char* kGatewayHelp =
    "A legacy machine's gateway (the paper's Raspberry Pi next to a closed PLC, §VII.B):\n"
    "it drives the machine's documented Modbus registers (a conveyor's belt, the box\n"
    "uploader or downloader, a legacy robot's controller), runs the machine as a PackML\n"
    "unit, and takes part in the Contract Net over DDS on its behalf: bids from its real\n"
    "state, awarded work done on the machine, INFORM-DONE or FAILURE to the product.\n"
    "A conveyor also answers transport REQUESTs with its belt's segments. Its OPC UA\n"
    "server publishes the machine's model (PLC registers as typed variables, Bad with the\n"
    "reason while the PLC is unreachable; PackML methods). It polls the\n"
    "PLC every poll period (20 ms by default) and prints a status line whenever the\n"
    "PackML state, the PLC link, the job or the queue changes (JSON lines with --json).\n"
    "A configuration error names FILE:LINE:COLUMN and nothing starts (exit status 2).";

constexpr const char* kGatewayConfigHelp =
    "gateway.yaml (examples per machine in configs/gateways/, docs/shop-floor.md):\n"
    "  machine: conveyor1         # the layout's machine\n"
    "  kind: conveyor             # conveyor, uploader, downloader, legacy-robot\n"
    "  layout: ../../layouts/prototype-line.yaml   # default: the built-in layout\n"
    "  start: execute             # stopped (default): wait for an operator's Reset, Start\n"
    "  modbus: {host: 127.0.0.1, port: 1502, poll_period_ms: 20, timeout_ms: 500}\n"
    "  opcua: {port: 4851}        # also modes, policies, users, anonymous, pki, nodesets\n"
    "  dds: {machining_domain: 10, conveying_domain: 11, interface: lo, partition: smartfactory}";

struct GatewayOptions {
  std::string config;
  bool json = false;
  bool check = false;
  double status_interval_s = 5;
  double duration_s = 0;
};

json segments_json(const fy::Gateway& g) {
  json out = json::array();
  for (const auto& s : g.segments()) {
    out.push_back({{"from", s.from},
                   {"to", s.to},
                   {"from_place", fy::place_index(g.layout(), s.from).value_or(0)},
                   {"to_place", fy::place_index(g.layout(), s.to).value_or(0)},
                   {"transit_ms", std::chrono::duration<double, std::milli>(s.transit_time).count()}});
  }
  return out;
}

void print_ready(const fy::GatewayProcess& p, bool as_json) {
  const fy::Gateway& g = p.gateway();
  const fy::GatewayConfig& c = g.config();
  const auto r = p.report();
  if (as_json) {
    std::cout << json{{"event", "ready"},
                      {"machine", c.controller.machine},
                      {"kind", fy::to_string(c.kind)},
                      {"endpoint", r.endpoint},
                      {"opcua", r.opcua_endpoint},
                      {"opcua_security", r.opcua_security},
                      {"poll_period_ms", c.modbus.poll_period.count()},
                      {"operations", g.operations()},
                      {"machining_domain", c.controller.dds.machining_domain},
                      {"conveying_domain", c.controller.dds.conveying_domain},
                      {"segments", segments_json(g)}}
                     .dump()
              << std::endl;
    return;
  }
  std::cout << fmt::format(
      "gateway {} ({}, {} {}): PLC {} every {} ms; DDS domains {}/{} on {}\n  OPC UA {} ({})\n",
      c.controller.machine, fy::to_string(c.kind), r.identification.manufacturer, r.identification.model,
      r.endpoint, c.modbus.poll_period.count(), c.controller.dds.machining_domain,
      c.controller.dds.conveying_domain, c.controller.dds.interface, r.opcua_endpoint, r.opcua_security);
  for (const auto& s : g.segments()) {
    std::cout << fmt::format("  segment {} -> {} ({:.3f} s)\n", s.from, s.to,
                             std::chrono::duration<double>(s.transit_time).count());
  }
  std::cout << std::flush;
}

void print_report(const fy::GatewayReport& r, bool as_json) {
  const auto& s = r.controller;
  if (as_json) {
    auto j = controller_status_json(r.identification.name, s, r.contract_net);
    j["link"] = r.link;
    j["operation"] = s.operation ? s.operation->type : "";
    j["confirms"] = r.contract_net.confirms;
    j["informs"] = r.informs;
    std::cout << j.dump() << std::endl;
    return;
  }
  std::cout << fmt::format("{}; link {}{}{}\n",
                           controller_status_text(r.identification.name, s, r.contract_net), r.link,
                           s.fault.empty() ? "" : "; fault: ", s.fault)
            << std::flush;
}

int run_gateway(const GatewayOptions& o) {
  auto setup = fy::load_gateway_config(o.config);
  if (!setup) {
    std::cerr << "gateway: " << setup.error().message << "\n";
    return kExitUsage;
  }
  if (o.check) {
    std::cout << fmt::format("{}: {} gateway for {} is valid\n", o.config, fy::to_string(setup->config.kind),
                             setup->config.controller.machine);
    return kExitOk;
  }
  auto& clock = SteadyClock::instance();
  auto process = fy::GatewayProcess::create(std::move(*setup), clock);
  if (!process) {
    std::cerr << "gateway: " << process.error().describe() << "\n";
    return process.error().code == Errc::invalid_argument ? kExitUsage : kExitFailure;
  }
  install_stop_signals();
  print_ready(**process, o.json);
  const auto end = o.duration_s > 0 ? clock.now() + std::chrono::duration_cast<std::chrono::nanoseconds>(
                                                        std::chrono::duration<double>(o.duration_s))
                                    : Clock::time_point::max();
  (*process)->run([&] { return stop_requested() || clock.now() >= end; },
                  [&](const fy::GatewayReport& r) { print_report(r, o.json); },
                  std::chrono::duration_cast<std::chrono::nanoseconds>(
                      std::chrono::duration<double>(o.status_interval_s)));
  print_report((*process)->report(), o.json);
  return kExitOk;
}

}  // namespace

void register_gateway(CLI::App& app, CommandResult& result) {
  auto o = std::make_shared<GatewayOptions>();
  auto* cmd = app.add_subcommand(
      "gateway",
      "A legacy machine's gateway: its PLC over Modbus TCP as a PackML unit, and its part in the "
      "Contract Net over DDS");
  cmd->add_option("--config", o->config, "The gateway's YAML file (machine, kind, Modbus endpoint, DDS)")
      ->required();
  cmd->add_flag("--json", o->json, "Status as JSON lines on stdout (events ready, status)");
  cmd->add_flag("--check", o->check, "Only check the configuration against its layout, then exit");
  cmd->add_option("--status-interval", o->status_interval_s,
                  "Seconds between status lines when nothing changes (0 = on changes only)")
      ->capture_default_str();
  cmd->add_option("--duration", o->duration_s, "Stop after this many seconds (0 = until SIGINT/SIGTERM)")
      ->capture_default_str();
  cmd->footer(std::string(kGatewayHelp) + "\n\n" + kGatewayConfigHelp);
  cmd->callback([o, &result] { result.exit_code = run_gateway(*o); });
}

}  // namespace sf::app
