// `smartfactory line --layout FILE`: the whole line as processes on this host (paper §VII), kept
// running by a supervisor. This file parses options and prints; the factory module
// (line_supervisor.hpp, supervisor.hpp) plans, starts, restarts and stops.
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <iostream>
#include <memory>
#include <string>
#include <system_error>

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <nlohmann/json.hpp>

#include "commands.hpp"
#include "sf/core/clock.hpp"
#include "sf/factory/line_hosts.hpp"
#include "sf/factory/line_supervisor.hpp"

namespace sf::app {
namespace {

using nlohmann::json;
namespace fs = std::filesystem;
namespace fy = sf::factory;

constexpr const char* kLineHelp =
    "The line on this host, one process per part of the paper's deployment (§VII), started\n"
    "in this order, each once the one before printed its ready line:\n"
    "  plant          `smartfactory plant`: the hardware (EtherCAT segments, Modbus PLCs)\n"
    "  <smart robot>  `smartfactory machine` per smart robot (its IPC)\n"
    "  <machine>      `smartfactory gateway` per belt, uploader, downloader, legacy robot\n"
    "  cloud          `smartfactory cloud --config FILE` with --cloud-config\n"
    "  orders         `smartfactory orders`: the order service; orders from --orders FILE\n"
    "                 and from `smartfactory order` (skipped when this build has none)\n"
    "Everything listens on loopback; the controllers' OPC UA servers count up from\n"
    "--opcua-base-port in that order, then the order service; all share one DDS partition.\n"
    "A process that exits is started again after a back-off (0.5 s doubling to 10 s; given\n"
    "up after 10 exits in a row); SIGINT or SIGTERM stops them in reverse order (exit 0).\n"
    "Exit 2: a bad layout or option, nothing started; exit 1: a process did not come up\n"
    "(its name and last log lines are printed, everything started is stopped).\n"
    "\n"
    "--hosts (root only, else exit 2): each process in a network namespace of its own\n"
    "(sf-XXXXXX-<process>, XXXXXX from the run directory), with an interface per protocol:\n"
    "  ecat0   a veth cable from the plant to each smart robot (raw EtherCAT, no IP)\n"
    "  field0  Modbus TCP, gateways to the plant's PLCs        10.77.1.0/24, plant 10.77.1.1\n"
    "  dds0    the Contract Net: orders, machines, gateways     10.77.2.0/24\n"
    "  opcua0  controllers and the order service to the cloud  10.77.3.0/24\n"
    "Each network is a bridge in the namespace sf-XXXXXX-net; a process's address ends in its\n"
    "place in the start order (10.77.N.1 the plant). Everything is removed on stop or a failed\n"
    "start; namespaces of the same names (a crashed run's) are removed first.";

constexpr const char* kRunDirHelp =
    "Run directory (--run-dir, default $TMPDIR/smartfactory-line-PID):\n"
    "  config/<name>.yaml      each controller's and the order service's configuration, written\n"
    "                          when the plant printed its endpoints (Modbus, EtherCAT addresses)\n"
    "  log/<process>.log       each process's stdout and stderr, kept across restarts";

struct LineCliOptions {
  fy::LineOptions line;
  bool json = false;
  double status_interval_s = 5;
  int opcua_base_port = 4850;
  int modbus_base_port = 0;
};

double uptime_seconds(Clock::duration d) {
  return std::chrono::duration<double>(d).count();
}

// A process's namespace and interfaces: {"netns": ..., "interfaces": [{network, name, address}]}.
json host_json(const fy::ProcessHost& host) {
  json interfaces = json::array();
  for (const auto& i : host.interfaces) {
    interfaces.push_back({{"network", fy::to_string(i.network)}, {"name", i.name}, {"address", i.address}});
  }
  return {{"netns", host.netns}, {"interfaces", interfaces}};
}

json networks_json(const fy::HostPlan& hosts) {
  json networks = json::array();
  for (const auto& n : hosts.networks) {
    networks.push_back({{"network", fy::to_string(n.kind)}, {"bridge", n.bridge}, {"subnet", n.cidr()}});
  }
  return {{"netns", hosts.line_netns}, {"networks", networks}};
}

json status_json(const fy::LinePlan& plan, const fy::Supervisor& s, std::string_view event) {
  json list = json::array();
  const auto status = s.status();
  for (std::size_t i = 0; i < status.size(); ++i) {
    const auto& p = status[i];
    json entry = {{"name", p.name},         {"role", fy::to_string(plan.processes[i].role)},
                  {"pid", p.pid},           {"state", fy::to_string(p.state)},
                  {"restarts", p.restarts}, {"uptime_s", uptime_seconds(p.uptime)},
                  {"opcua", p.opcua},       {"last_exit", p.last_exit},
                  {"log", p.log.string()}};
    if (const auto* host = plan.host_of(plan.processes[i])) {
      entry.update(host_json(*host));
    }
    list.push_back(std::move(entry));
  }
  json out = {{"event", event},
              {"line", plan.layout.line},
              {"run_dir", plan.options.run_dir.string()},
              {"partition", plan.options.partition},
              {"processes", list}};
  if (plan.hosts) {
    out["hosts"] = networks_json(*plan.hosts);
  }
  return out;
}

// Each process's namespace and interfaces, below the table (the view of the `ready` event).
void print_hosts(const fy::LinePlan& plan) {
  const auto& hosts = *plan.hosts;
  std::cout << fmt::format("networks (bridges in {}):", hosts.line_netns);
  for (const auto& n : hosts.networks) {
    std::cout << fmt::format(" {} {}", fy::to_string(n.kind), n.cidr());
  }
  std::cout << "\n" << fmt::format("{:<15} {:<28} {}\n", "PROCESS", "NAMESPACE", "INTERFACES");
  for (const auto& h : hosts.hosts) {
    std::string interfaces;
    for (const auto& i : h.interfaces) {
      interfaces +=
          fmt::format("{}{} {}", interfaces.empty() ? "" : ", ", i.name,
                      i.address.empty() ? fmt::format("({})", fy::to_string(i.network)) : i.address);
    }
    std::cout << fmt::format("{:<15} {:<28} {}\n", h.process, h.netns, interfaces);
  }
  std::cout << std::flush;
}

void print_table(const fy::LinePlan& plan, const fy::Supervisor& s) {
  const auto status = s.status();
  std::size_t up = 0;
  for (const auto& p : status) {
    up += p.state == fy::ProcessState::up ? 1U : 0U;
  }
  if (::isatty(STDOUT_FILENO) == 1) {
    std::cout << "\033[H\033[J";  // a refreshed view, not a scrolling log
  }
  std::cout << fmt::format("line {}: {}/{} up; run directory {}; DDS partition {}\n", plan.layout.line, up,
                           status.size(), plan.options.run_dir.string(), plan.options.partition);
  std::cout << fmt::format("{:<15} {:<8} {:<10} {:>8} {:>8} {:>10}  {}\n", "PROCESS", "ROLE", "STATE", "PID",
                           "RESTARTS", "UPTIME", "OPC UA / LAST EXIT");
  for (std::size_t i = 0; i < status.size(); ++i) {
    const auto& p = status[i];
    std::cout << fmt::format("{:<15} {:<8} {:<10} {:>8} {:>8} {:>8.1f} s  {}\n", p.name,
                             fy::to_string(plan.processes[i].role), fy::to_string(p.state),
                             p.pid > 0 ? std::to_string(p.pid) : "-", p.restarts, uptime_seconds(p.uptime),
                             p.state == fy::ProcessState::up ? p.opcua : p.last_exit);
  }
  std::cout << std::flush;
}

void print_status(const fy::LinePlan& plan, const fy::Supervisor& s, bool as_json, std::string_view event) {
  if (as_json) {
    std::cout << status_json(plan, s, event).dump() << std::endl;
    return;
  }
  print_table(plan, s);
  if (plan.hosts && event == "ready") {
    print_hosts(plan);
  }
}

// The plan's namespaces made real, reporting what a crashed run left behind.
Result<std::unique_ptr<fy::HostNetworks>> make_networks(const fy::LinePlan& plan) {
  std::vector<std::string> removed;
  auto networks = fy::HostNetworks::create(*plan.hosts, &removed);
  if (!removed.empty()) {
    std::cerr << fmt::format("line: removed namespaces an earlier run left: {}\n", fmt::join(removed, " "));
  }
  if (networks) {
    std::cerr << fmt::format("line: {} network namespaces {}-*\n", plan.hosts->namespaces().size(),
                             plan.hosts->prefix);
  }
  return networks;
}

Result<fy::LinePlan> plan(LineCliOptions& o) {
  if (o.opcua_base_port < 0 || o.opcua_base_port > 65535 || o.modbus_base_port < 0 ||
      o.modbus_base_port > 65535) {
    return make_error(Errc::invalid_argument, "a base port is 0 (a free range) or 1..65535");
  }
  if (o.status_interval_s < 0) {
    return make_error(Errc::invalid_argument, "--status-interval is 0 (on changes only) or more seconds");
  }
  o.line.opcua_base_port = static_cast<std::uint16_t>(o.opcua_base_port);
  o.line.modbus_base_port = static_cast<std::uint16_t>(o.modbus_base_port);
  std::error_code ec;
  o.line.program = fs::read_symlink("/proc/self/exe", ec);
  if (ec) {
    return make_error(Errc::io, fmt::format("cannot find this program: {}", ec.message()));
  }
  o.line.order_service = fy::has_command(o.line.program, "orders");
  if (!o.line.order_service) {
    std::cerr << "line: this build has no `orders` command; the line runs without the order service\n";
  }
  return fy::plan_line(o.line);
}

int run_line(LineCliOptions& o) {
  if (o.line.hosts) {
    if (auto st = fy::hosts_supported(); !st) {
      std::cerr << "line: " << st.error().message << "\n";
      return kExitUsage;
    }
  }
  auto p = plan(o);
  if (!p) {
    std::cerr << "line: " << p.error().message << "\n";
    return kExitUsage;
  }
  if (auto st = fy::prepare_run_dir(*p); !st) {
    std::cerr << "line: " << st.error().message << "\n";
    return kExitUsage;
  }
  std::cerr << fmt::format("line: {} processes; run directory {}; DDS partition {}\n", p->processes.size(),
                           p->options.run_dir.string(), p->options.partition);
  install_stop_signals();
  std::unique_ptr<fy::HostNetworks> networks;  // removed after the supervisor stopped everything
  if (p->hosts) {
    auto made = make_networks(*p);
    if (!made) {
      std::cerr << "line: " << made.error().message << "\n";
      return kExitFailure;
    }
    networks = std::move(*made);
  }
  auto& clock = SteadyClock::instance();
  fy::Supervisor supervisor(fy::supervised_processes(*p), fy::line_supervisor_options(*p), clock);
  if (auto st = supervisor.start(stop_requested); !st) {
    if (stop_requested()) {
      return kExitOk;
    }
    std::cerr << "line: " << st.error().message << "\n";
    return kExitFailure;
  }
  print_status(*p, supervisor, o.json, "ready");
  const auto interval =
      std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(o.status_interval_s));
  auto last_print = clock.now();
  auto printed = supervisor.changes();
  supervisor.run(stop_requested, [&] {
    const bool due = interval.count() > 0 && clock.now() - last_print >= interval;
    if (due || supervisor.changes() != printed) {
      print_status(*p, supervisor, o.json, "status");
      last_print = clock.now();
      printed = supervisor.changes();
    }
  });
  std::cerr << "line: stopping\n";
  supervisor.stop();
  print_status(*p, supervisor, o.json, "stopped");
  return kExitOk;
}

}  // namespace

void register_line(CLI::App& app, CommandResult& result) {
  auto o = std::make_shared<LineCliOptions>();
  auto* cmd = app.add_subcommand(
      "line", "The line as processes on this host (plant, machines, gateways, order service), supervised");
  cmd->description(kLineHelp);
  cmd->add_option("--layout", o->line.layout_file, "Layout file (default: the built-in prototype line)");
  cmd->add_option("--run-dir", o->line.run_dir, "Where configurations and logs go (created)");
  cmd->add_option("--opcua-base-port", o->opcua_base_port, "First OPC UA port (0 = a free range)")
      ->capture_default_str();
  cmd->add_option("--modbus-base-port", o->modbus_base_port,
                  "First Modbus TCP port of the plant's PLCs (0 = a free range)")
      ->capture_default_str();
  cmd->add_option("--partition", o->line.partition, "DDS partition (default: one of this run's own)");
  cmd->add_option("--orders", o->line.orders_file, "Orders file the order service takes at its start");
  cmd->add_option("--cloud-config", o->line.cloud_config,
                  "Also run `smartfactory cloud` with this cloud.yaml");
  cmd->add_option(
      "--historian", o->line.historian,
      "Also run the cloud, configured for the line, into this historian (sqlite:PATH, postgresql://...)");
  cmd->add_option("--http", o->line.http_port,
                  "The cloud's dashboard on this port (0 = any free port, see the cloud's log; -1 = off)")
      ->capture_default_str();
  cmd->add_option(
      "--web-users", o->line.web_users,
      "Users of the dashboard (`smartfactory opcua users` file: consumer, viewer, operator, ...)");
  add_tls_options(cmd, o->line.tls_cert, o->line.tls_key);
  cmd->add_flag(
      "--hosts", o->line.hosts,
      "Each process in a network namespace of its own, an interface per protocol (root; see above)");
  cmd->add_flag("--json", o->json, "Status as JSON lines on stdout (events ready, status, stopped)");
  cmd->add_option("--status-interval", o->status_interval_s,
                  "Seconds between status views (0 = only when a process changes state)")
      ->capture_default_str();
  cmd->footer(kRunDirHelp);
  cmd->callback([o, &result] { result.exit_code = run_line(*o); });
}

}  // namespace sf::app
