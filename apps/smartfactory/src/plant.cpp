// `smartfactory plant ...`: the plant simulation (libs/plant) — every piece
// of hardware of the candy-packing line behind the faces real hardware has:
// EtherCAT segments for the smart robots, Modbus TCP servers for the PLCs and
// legacy robot controllers. This file parses options and prints; the plant
// module does the work.
#include <chrono>
#include <cstdio>
#include <iostream>
#include <map>
#include <memory>
#include <string>
#include <thread>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "commands.hpp"
#include "sf/line/layout.hpp"
#include "sf/line/ontology.hpp"
#include "sf/line/registers.hpp"
#include "sf/plant/control.hpp"
#include "sf/plant/host.hpp"

namespace sf::app {
namespace {

using namespace std::chrono_literals;
using nlohmann::json;

constexpr const char* kPlantHelp =
    "The plant simulation: the paper's candy-packing line (§VII) as hardware a real\n"
    "control system can drive. Smart robots are EtherCAT segments (the smart\n"
    "controller: 8 CiA 402 axes, 32 DI, 32 DO) on EtherCAT-in-UDP or a raw interface;\n"
    "conveyor PLCs, box uploader/downloader PLCs and legacy robot controllers are\n"
    "Modbus TCP servers (register maps: `plant registers`, docs/plant.md). With no\n"
    "options it serves the default layout (layouts/prototype-line.yaml) on loopback\n"
    "and prints where each face listens. Faults and snapshots: `plant faults`,\n"
    "`plant snapshot` against the control port it prints.";

struct ServeOptions {
  std::string layout;
  std::string speed = "1";
  std::uint64_t seed = 1;
  bool json = false;
  double duration_s = 0;
  double status_interval_s = 5;
  sf::plant::HostOptions host;
  std::vector<std::string> ecat_ifaces;
};

Result<sf::plant::Layout> load(const std::string& file) {
  return file.empty() ? sf::plant::default_layout() : sf::plant::load_layout(file);
}

void print_endpoints(const std::vector<sf::plant::Endpoint>& endpoints, bool as_json) {
  if (as_json) {
    json list = json::array();
    for (const auto& e : endpoints) {
      list.push_back({{"machine", e.machine}, {"protocol", e.protocol}, {"address", e.address}});
    }
    std::cout << json{{"endpoints", list}}.dump() << std::endl;
    return;
  }
  for (const auto& e : endpoints) {
    std::cout << fmt::format("{:<16} {:<14} {}\n", e.machine, e.protocol, e.address);
  }
  std::cout << std::flush;
}

Status parse_ifaces(ServeOptions& o) {
  for (const auto& item : o.ecat_ifaces) {
    const auto eq = item.find('=');
    if (eq == std::string::npos || eq == 0 || eq + 1 == item.size()) {
      return make_error(Errc::invalid_argument,
                        fmt::format("--ecat-iface '{}': expected ROBOT=INTERFACE", item));
    }
    o.host.ecat_interfaces[item.substr(0, eq)] = item.substr(eq + 1);
  }
  return {};
}

int serve(ServeOptions& o) {
  auto layout = load(o.layout);
  if (!layout) {
    std::cerr << "plant: " << layout.error().message << "\n";
    return kExitUsage;
  }
  if (auto st = parse_ifaces(o); !st) {
    std::cerr << "plant: " << st.error().message << "\n";
    return kExitUsage;
  }
  std::unique_ptr<Clock> clock;
  if (o.speed == "max") {
    clock = std::make_unique<ManualClock>();
    o.host.real_time = false;
  } else {
    double factor = 0;
    try {
      factor = std::stod(o.speed);
    } catch (const std::exception&) {
      factor = 0;
    }
    if (!(factor > 0.0 && factor <= 1000.0)) {
      std::cerr << "plant: --speed must be 1, a factor up to 1000, or max\n";
      return kExitUsage;
    }
    clock = factor == 1.0 ? std::unique_ptr<Clock>(std::make_unique<SteadyClock>())
                          : std::unique_ptr<Clock>(std::make_unique<ScaledClock>(factor));
  }
  sf::plant::Plant plant(std::move(*layout), *clock, sf::plant::PlantOptions{o.seed});
  install_stop_signals();
  auto host = sf::plant::PlantHost::start(plant, *clock, o.host);
  if (!host) {
    std::cerr << "plant: " << host.error().message << "\n";
    return kExitFailure;
  }
  print_endpoints((*host)->endpoints(), o.json);
  const auto start = std::chrono::steady_clock::now();
  auto next_status = start + std::chrono::duration<double>(o.status_interval_s);
  while (!stop_requested()) {
    std::this_thread::sleep_for(50ms);
    const auto now = std::chrono::steady_clock::now();
    if (o.duration_s > 0 && now - start >= std::chrono::duration<double>(o.duration_s)) {
      break;
    }
    if (o.status_interval_s > 0 && now >= next_status) {
      next_status += std::chrono::duration<double>(o.status_interval_s);
      auto lock = plant.lock();
      const auto s = plant.snapshot();
      std::fprintf(stderr, "plant: t=%.1f s (%.1fx), %zu boxes on the line, %llu done, %zu faults\n",
                   std::chrono::duration<double>(s.time).count(), (*host)->pace(), s.boxes.size(),
                   static_cast<unsigned long long>(s.counters.downloaded), s.faults.size());
    }
  }
  (*host)->stop();
  return kExitOk;
}

// host:port of the control port.
Result<std::pair<std::string, std::uint16_t>> control_address(const std::string& text) {
  const auto colon = text.rfind(':');
  if (colon == std::string::npos) {
    return make_error(Errc::invalid_argument, fmt::format("--control '{}': expected HOST:PORT", text));
  }
  try {
    const int port = std::stoi(text.substr(colon + 1));
    if (port > 0 && port < 65536) {
      return std::pair{text.substr(0, colon), static_cast<std::uint16_t>(port)};
    }
  } catch (const std::exception&) {
  }
  return make_error(Errc::invalid_argument, fmt::format("--control '{}': port is not 1..65535", text));
}

// Sends one control request; prints the answer (raw JSON with --json).
int ask(const std::string& control, const json& request, bool as_json, void (*print)(const json&)) {
  auto address = control_address(control);
  if (!address) {
    std::cerr << "plant: " << address.error().message << "\n";
    return kExitUsage;
  }
  auto answer = sf::plant::control_request(address->first, address->second, request.dump());
  if (!answer) {
    std::cerr << "plant: " << answer.error().message << "\n";
    return kExitFailure;
  }
  const json reply = json::parse(*answer, nullptr, false);
  if (reply.is_discarded() || !reply.value("ok", false)) {
    std::cerr << "plant: " << (reply.is_discarded() ? *answer : reply.value("error", *answer)) << "\n";
    return kExitFailure;
  }
  if (as_json) {
    std::cout << reply.dump() << std::endl;
  } else if (print != nullptr) {
    print(reply);
  }
  return kExitOk;
}

void print_snapshot(const json& reply) {
  const json& s = reply["snapshot"];
  std::cout << fmt::format("t = {:.3f} s, {} events\n", s["time"].get<double>(),
                           s["events"].get<std::uint64_t>());
  for (const auto& b : s["belts"]) {
    std::cout << fmt::format(
        "belt {:<10} motor {:<3} {:.2f} m/s{}{}\n", b["name"].get<std::string>(),
        b["motor"].get<bool>() ? "on" : "off", b["speed_mps"].get<double>(),
        b["jammed"].get<bool>() ? " JAMMED" : "",
        b["exit"].get<std::string>().empty() ? "" : " → " + b["exit"].get<std::string>());
  }
  for (const auto& b : s["boxes"]) {
    int filled = 0;
    for (const auto& slot : b["slots"]) {
      filled += slot.get<std::string>().empty() ? 0 : 1;
    }
    std::cout << fmt::format(
        "box {:<4} {:<10} on {} at {:.3f} m{} ({}/{} slots filled)\n", b["id"].get<int>(),
        b["type"].get<std::string>(), b["belt"].get<std::string>(), b["s"].get<double>(),
        b["station"].get<std::string>().empty() ? "" : ", at " + b["station"].get<std::string>(), filled,
        b["slots"].size());
  }
  for (const auto& f : s["faults"]) {
    std::cout << "fault " << f.get<std::string>() << "\n";
  }
  const json& c = s["counters"];
  std::cout << fmt::format("uploaded {}, downloaded {}, placed {}, dropped {}, boxes lost {}\n",
                           c["uploaded"].get<int>(), c["downloaded"].get<int>(), c["placed"].get<int>(),
                           c["dropped"].get<int>(), c["boxes_lost"].get<int>());
}

void print_faults(const json& reply) {
  for (const auto& f : reply["faults"]) {
    std::cout << f.get<std::string>() << "\n";
  }
}

void print_events(const json& reply) {
  for (const auto& e : reply["events"]) {
    std::cout << fmt::format("{:.6f} {} {}", e["t"].get<double>(), e["kind"].get<std::string>(),
                             e["where"].get<std::string>());
    for (const char* key : {"box", "slot", "candy", "detail"}) {
      if (e.contains(key)) {
        std::cout << " " << key << "=" << e[key].dump();
      }
    }
    std::cout << "\n";
  }
}

void register_faults(CLI::App& plant, CommandResult& result) {
  auto* faults =
      plant.add_subcommand("faults", "Inject, clear or list faults in a running plant (its control port)");
  faults->require_subcommand(1);
  static std::string control;
  static std::string fault_text;
  static double at = -1;
  static double duration = -1;
  static bool as_json = false;
  faults->add_option("--control", control, "HOST:PORT of the plant's control port (printed at its start)")
      ->required();
  faults->add_flag("--json", as_json, "Print the answer as JSON");
  const char* kinds =
      "jam:BELT, dispenser-empty:DISPENSER, mixup:DISPENSER, axis-fault:ROBOT:AXIS[:CODE], cable-cut:ROBOT,\n"
      "plc-unreachable:MACHINE, plc-exception:MACHINE[:CODE], overheat:ROBOT, box-drop:BOX";
  for (const char* op : {"inject", "clear"}) {
    auto* cmd = faults->add_subcommand(op, std::string(op) + " a fault: " + kinds);
    cmd->add_option("fault", fault_text, "The fault, e.g. jam:conveyor2")->required();
    if (std::string(op) == "inject") {
      cmd->add_option("--at", at, "Inject it this many simulated seconds from now");
      cmd->add_option("--for", duration, "Clear it again after this many simulated seconds");
    }
    cmd->callback([&result, op] {
      json request{{"op", op}, {"fault", fault_text}};
      if (at >= 0) {
        request["at"] = at;
      }
      if (duration >= 0) {
        request["for"] = duration;
      }
      result.exit_code = ask(control, request, as_json, nullptr);
    });
  }
  faults->add_subcommand("list", "List the faults injected and not cleared")->callback([&result] {
    result.exit_code = ask(control, json{{"op", "faults"}}, as_json, print_faults);
  });
}

void register_observe(CLI::App& plant, CommandResult& result) {
  static std::string control;
  static bool as_json = false;
  static std::uint64_t since = 0;
  auto* snapshot =
      plant.add_subcommand("snapshot", "Print a running plant's world: belts, boxes, faults, counters");
  snapshot->add_option("--control", control, "HOST:PORT of the plant's control port")->required();
  snapshot->add_flag("--json", as_json, "The whole snapshot as JSON");
  snapshot->callback([&result] {
    result.exit_code = ask(control, json{{"op", "snapshot"}}, as_json, print_snapshot);
  });
  auto* events = plant.add_subcommand("events", "Print a running plant's event log (boxes, candies, faults)");
  events->add_option("--control", control, "HOST:PORT of the plant's control port")->required();
  events->add_option("--since", since, "First event number (0 = the oldest kept)");
  events->add_flag("--json", as_json, "Print the answer as JSON");
  events->callback([&result] {
    result.exit_code = ask(control, json{{"op", "events"}, {"since", since}}, as_json, print_events);
  });
}

void register_tools(CLI::App& plant, CommandResult& result) {
  static std::string layout_file;
  auto* check =
      plant.add_subcommand("check", "Check a layout file and summarise it (exit 2 when it is refused)");
  check->add_option("--layout", layout_file, "Layout file (default: the built-in prototype line)");
  check->callback([&result] {
    auto layout = load(layout_file);
    if (!layout) {
      std::cerr << "plant: " << layout.error().message << "\n";
      result.exit_code = kExitUsage;
      return;
    }
    std::cout << fmt::format("{}: {} belts, {} robots, {} dispensers, {} candy types, {} box types\n",
                             layout->label, layout->belts.size(), layout->robots.size(),
                             layout->dispensers.size(), layout->catalog.candy_types.size(),
                             layout->catalog.box_types.size());
  });
  auto* registers =
      plant.add_subcommand("registers", "Print the Modbus register maps of the legacy controllers");
  registers->callback([] {
    std::cout << "## Conveyor PLC\n\n" << sf::plant::markdown(sf::plant::conveyor_plc::map());
    std::cout << "\n## Box uploader and downloader PLC\n\n"
              << sf::plant::markdown(sf::plant::transfer_plc::map());
    std::cout << "\n## Legacy robot controller\n\n"
              << sf::plant::markdown(sf::plant::robot_controller::map());
  });
  auto* ontology =
      plant.add_subcommand("ontology",
                           "Print the line's individuals for the candy-factory ontology (Turtle), derived "
                           "from a layout; the default gives ontology/prototype-line.ttl");
  ontology->add_option("--layout", layout_file, "Layout file (default: the built-in prototype line)");
  ontology->callback([&result] {
    auto layout = load(layout_file);
    if (!layout) {
      std::cerr << "plant: " << layout.error().message << "\n";
      result.exit_code = kExitUsage;
      return;
    }
    std::cout << sf::line::line_turtle(*layout,
                                       layout_file.empty() ? "layouts/prototype-line.yaml" : layout_file);
  });
}

}  // namespace

void register_plant(CLI::App& app, CommandResult& result) {
  auto* plant = app.add_subcommand("plant", kPlantHelp);
  plant->require_subcommand(0, 1);
  static ServeOptions o;
  plant->add_option("--layout", o.layout, "Layout file (default: the built-in layouts/prototype-line.yaml)");
  plant->add_option("--speed", o.speed, "1 = real time, N = N times faster, max = as fast as the CPU allows");
  plant->add_option("--seed", o.seed, "Seed of the plant's random variations (machine cycle times)");
  plant->add_flag("--json", o.json, "Print the endpoints as JSON");
  plant->add_option("--duration", o.duration_s, "Stop after this many seconds (0 = until Ctrl-C)");
  plant->add_option("--status-interval", o.status_interval_s,
                    "Seconds between status lines on stderr (0 = none)");
  plant->add_option("--modbus-host", o.host.modbus_host, "Address the Modbus TCP servers listen on");
  plant->add_option("--modbus-port", o.host.modbus_port,
                    "First Modbus port, counting up per PLC (0 = free ports)");
  plant->add_option("--ecat-host", o.host.ecat_host, "Address the EtherCAT-in-UDP segments listen on");
  plant->add_option("--ecat-port", o.host.ecat_port,
                    "First EtherCAT UDP port, counting up per smart robot (0 = free)");
  plant->add_option("--ecat-iface", o.ecat_ifaces,
                    "ROBOT=INTERFACE: serve that robot's segment on a raw interface");
  plant->add_option("--control-host", o.host.control_host, "Address of the control port");
  plant->add_option("--control-port", o.host.control_port, "Control port (0 = a free port)");
  plant->callback([plant, &result] {
    if (plant->get_subcommands().empty()) {
      result.exit_code = serve(o);
    }
  });
  register_faults(*plant, result);
  register_observe(*plant, result);
  register_tools(*plant, result);
}

}  // namespace sf::app
