// `smartfactory ecat sim|scan|run|sdo`: the EtherCAT module from the command line.
//   sim   serves an emulated segment on an interface (the slaves' side)
//   scan  lists the slaves of a segment
//   run   brings the segment to OP and exchanges process data cyclically
//   sdo   lists, reads and writes a slave's object dictionary (ecat_sdo.cpp)
// scan and run take --iface IF for a real wire or --sim SPEC for an emulated
// segment in this process (no root, no NIC needed).
#include <chrono>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <thread>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "commands.hpp"
#include "ecat_session.hpp"
#include "sf/core/clock.hpp"
#include "sf/core/log.hpp"
#include "sf/ethercat/master/master.hpp"
#include "sf/ethercat/slave/devices.hpp"
#include "sf/ethercat/slave/segment.hpp"

namespace sf::app {
namespace {

namespace ecat = sf::ethercat;
using nlohmann::json;
using namespace std::chrono_literals;

struct SimOptions {
  LinkChoice link;
  std::string slaves;
  std::string report;
  double drop_rate = 0.0;
};

struct MasterCliOptions {
  LinkChoice link;
  bool json = false;
  unsigned cycle_us = 1000;
  double duration_s = 10.0;
  bool dc = true;
  std::string final_state = "init";
};

json slave_report(ecat::slave::Segment& segment, std::size_t position) {
  auto& esc = segment.slave(position);
  return json{{"position", position},
              {"kind", std::string{esc.device().kind()}},
              {"connected", segment.connected(position)},
              {"al_state", esc.al_status().to_string()},
              {"al_status_code", esc.al_status_code()},
              {"station_address", esc.station_address()},
              {"last_outputs", to_hex(esc.last_outputs(), 4096)},
              {"last_inputs", to_hex(esc.last_inputs(), 4096)},
              {"outputs_safe", esc.device().outputs_safe()},
              {"watchdog_expirations", esc.watchdog_expirations()}};
}

int run_sim(const SimOptions& o) {
  auto& clock = SteadyClock::instance();
  ecat::slave::SegmentOptions seg_options;
  seg_options.drop_probability = o.drop_rate;
  auto segment = ecat::slave::Segment::create(o.slaves, clock, seg_options);
  if (!segment) {
    std::cerr << "ecat sim: --slaves: " << segment.error().message << "\n";
    return kExitUsage;
  }
  set_input_pattern(**segment);
  auto link = open_link(o.link, clock);
  if (!link) {
    std::cerr << "ecat sim: " << link.error().describe() << "\n";
    return kExitFailure;
  }
  // The runner thread inherits real-time scheduling where permitted: an
  // emulated segment must answer within the master's frame timeout.
  const bool realtime = try_realtime(70);
  ecat::slave::SegmentRunner runner{**segment, **link};
  if (auto st = runner.start(); !st) {
    std::cerr << "ecat sim: " << st.error().describe() << "\n";
    return kExitFailure;
  }
  install_stop_signals();
  std::fprintf(stderr, "ecat sim: %zu slaves (%s) on %s%s; Ctrl-C to stop\n", (*segment)->size(),
               o.slaves.c_str(), (*link)->name().c_str(), realtime ? " (SCHED_FIFO)" : "");
  auto last = runner.counters();
  auto last_print = clock.now();
  while (!stop_requested()) {
    std::this_thread::sleep_for(100ms);
    if (clock.now() - last_print >= 1s) {
      const auto c = runner.counters();
      std::fprintf(stderr, "ecat sim: %llu frames/s, %llu answered, %llu dropped, %llu errors\n",
                   static_cast<unsigned long long>(c.frames - last.frames),
                   static_cast<unsigned long long>(c.answered), static_cast<unsigned long long>(c.dropped),
                   static_cast<unsigned long long>(c.errors));
      last = c;
      last_print = clock.now();
    }
  }
  runner.stop();
  // Let the watchdogs see the silence the stop left behind.
  (*segment)->poll();
  if (!o.report.empty()) {
    json report;
    const auto c = runner.counters();
    report["frames"] = c.frames;
    report["answered"] = c.answered;
    report["dropped"] = c.dropped;
    {
      auto guard = (*segment)->lock();
      for (std::size_t i = 0; i < (*segment)->size(); ++i) {
        report["slaves"].push_back(slave_report(**segment, i));
      }
    }
    std::ofstream out{o.report};
    out << report.dump(2) << "\n";
    if (!out) {
      std::cerr << "ecat sim: cannot write report " << o.report << "\n";
      return kExitFailure;
    }
  }
  return kExitOk;
}

std::vector<std::string> mailbox_protocols(std::uint16_t bits) {
  static constexpr std::pair<std::uint16_t, const char*> kNames[] = {
      {ecat::sii::protocol::kAoE, "AoE"}, {ecat::sii::protocol::kEoE, "EoE"},
      {ecat::sii::protocol::kCoE, "CoE"}, {ecat::sii::protocol::kFoE, "FoE"},
      {ecat::sii::protocol::kSoE, "SoE"}, {ecat::sii::protocol::kVoE, "VoE"}};
  std::vector<std::string> out;
  for (const auto& [bit, name] : kNames) {
    if ((bits & bit) != 0) {
      out.emplace_back(name);
    }
  }
  return out;
}

using Mappings = std::vector<ecat::master::PdoMapping>;

json scan_json(const ecat::master::Master& master, const Mappings& pdo) {
  json slaves = json::array();
  for (const auto& s : master.slaves()) {
    const auto& map = pdo.at(s.position);
    slaves.push_back({{"position", s.position},
                      {"address", s.station},
                      {"vendor_id", s.sii.identity.vendor_id},
                      {"product_code", s.sii.identity.product_code},
                      {"revision", s.sii.identity.revision},
                      {"serial", s.sii.identity.serial},
                      {"name", s.name()},
                      {"input_bits", map.input_bits},
                      {"output_bits", map.output_bits},
                      {"pdo_source", map.source == ecat::master::PdoMapping::Source::coe   ? "CoE"
                                     : map.source == ecat::master::PdoMapping::Source::sii ? "SII"
                                                                                           : "none"},
                      {"mailbox", s.mailbox.present() ? mailbox_protocols(s.mailbox.protocols)
                                                      : std::vector<std::string>{}},
                      {"dc", s.esc.dc_supported()}});
  }
  return json{{"slaves", slaves}};
}

void print_scan_table(const ecat::master::Master& master, const Mappings& pdo) {
  std::printf("%-4s %-7s %-10s %-10s %-10s %-40s %6s %6s %-9s %s\n", "pos", "address", "vendor", "product",
              "revision", "name", "in", "out", "mailbox", "dc");
  for (const auto& s : master.slaves()) {
    std::string mbx;
    for (const auto& p : mailbox_protocols(s.mailbox.present() ? s.mailbox.protocols : 0)) {
      mbx += (mbx.empty() ? "" : ",") + p;
    }
    std::printf("%-4u 0x%04x  0x%08x 0x%08x 0x%08x %-40s %6u %6u %-9s %s\n", s.position, s.station,
                s.sii.identity.vendor_id, s.sii.identity.product_code, s.sii.identity.revision,
                s.name().c_str(), pdo.at(s.position).input_bits, pdo.at(s.position).output_bits,
                mbx.empty() ? "-" : mbx.c_str(), s.esc.dc_supported() ? "yes" : "no");
  }
}

int run_scan(const MasterCliOptions& o) {
  auto session = EcatSession::open(o.link);
  if (!session) {
    std::cerr << "ecat scan: " << session.error().describe() << "\n";
    return kExitFailure;
  }
  auto& master = (*session)->master();
  auto count = master.scan();
  if (!count) {
    std::cerr << "ecat scan: " << count.error().describe() << "\n";
    return kExitFailure;
  }
  // The PDO mapping of CoE slaves is read through the mailbox: PREOP.
  int rc_preop = kExitOk;
  if (auto st = master.request_state(ecat::AlState::PreOp); !st) {
    std::cerr << "ecat scan: PREOP: " << st.error().describe() << "\n";
    rc_preop = kExitFailure;
  }
  Mappings pdo(master.slave_count());
  int rc = rc_preop;
  for (std::size_t i = 0; i < master.slave_count(); ++i) {
    auto mapping = master.read_pdo_mapping(i);
    if (mapping) {
      pdo[i] = std::move(*mapping);
    } else {
      // Still listed (as 0/0 bits, PDO source "none"), but the scan failed.
      std::cerr << "ecat scan: slave " << i << ": PDO mapping: " << mapping.error().describe() << "\n";
      rc = kExitFailure;
    }
  }
  if (o.json) {
    std::cout << scan_json(master, pdo).dump(2) << "\n";
  } else {
    print_scan_table(master, pdo);
  }
  return rc;
}

// The device models a segment spec can name, one per line (from the library's table).
std::string kinds_help() {
  std::string out;
  for (const auto& model : ecat::slave::device_models()) {
    out += fmt::format("  {:<17} {}\n", model.name, model.summary);
  }
  return out;
}

}  // namespace

void register_ecat(CLI::App& app, CommandResult& result) {
  auto* ecat_cmd = app.add_subcommand("ecat", "EtherCAT machine network: emulated slaves, master tools");
  ecat_cmd->require_subcommand(1);
  ecat_cmd->footer(
      "Interfaces need root (raw AF_PACKET sockets). Try it without a NIC:\n"
      "  smartfactory ecat run --sim smart-controller:1,digital-io:2 --duration 5");

  auto sim = std::make_shared<SimOptions>();
  auto* sim_cmd = ecat_cmd->add_subcommand(
      "sim", "Emulate a segment of EtherCAT slaves on an interface until signalled (SIGINT/SIGTERM)");
  sim_cmd->add_option("--iface", sim->link.iface, "Network interface to answer frames on (e.g. a veth end)")
      ->required();
  sim_cmd
      ->add_option("--slaves", sim->slaves,
                   "Segment, in ring order: KIND[:COUNT],... with KIND one of\n" + kinds_help())
      ->required();
  sim_cmd->add_option("--pcap", sim->link.pcap, "Record every frame received and sent to this pcap file");
  add_busy_poll_option(*sim_cmd, sim->link);
  sim_cmd->add_option("--drop-rate", sim->drop_rate, "Probability (0..1) that a frame is lost in the segment")
      ->check(CLI::Range(0.0, 1.0));
  sim_cmd->add_option("--report", sim->report,
                      "On exit, write each slave's state and process data as JSON here");
  sim_cmd->callback([sim, &result] { result.exit_code = run_sim(*sim); });

  auto scan = std::make_shared<MasterCliOptions>();
  auto* scan_cmd = ecat_cmd->add_subcommand(
      "scan", "List the slaves of a segment: position, address, identity, name, PDO sizes, mailbox, DC");
  add_link_options(*scan_cmd, scan->link);
  scan_cmd->add_flag("--json", scan->json, "Print JSON instead of a table");
  scan_cmd->callback([scan, &result] { result.exit_code = run_scan(*scan); });

  register_ecat_sdo(*ecat_cmd, result);

  auto run = std::make_shared<MasterCliOptions>();
  auto* run_cmd = ecat_cmd->add_subcommand(
      "run", "Bring the segment to OP and exchange process data cyclically; print cycle statistics");
  add_link_options(*run_cmd, run->link);
  run_cmd->add_option("--cycle-us", run->cycle_us, "Cycle time in microseconds")
      ->check(CLI::Range(50U, 1'000'000U))
      ->capture_default_str();
  run_cmd->add_option("--duration", run->duration_s, "How long to run, in seconds")
      ->check(CLI::Range(0.0, 1e6))
      ->capture_default_str();
  run_cmd->add_flag(
      "--no-dc", [run](std::int64_t) { run->dc = false; }, "Do not configure distributed clocks");
  run_cmd->add_flag("--json", run->json, "Print the result as JSON");
  run_cmd
      ->add_option("--final-state", run->final_state,
                   "State to leave the segment in on exit, after disabling the drives (op keeps it running "
                   "until the slaves' watchdogs trip)")
      ->check(CLI::IsMember({"init", "preop", "safeop", "op"}, CLI::ignore_case))
      ->capture_default_str();
  run_cmd->callback([run, &result] {
    static const std::map<std::string, ecat::AlState> kStates{{"init", ecat::AlState::Init},
                                                              {"preop", ecat::AlState::PreOp},
                                                              {"safeop", ecat::AlState::SafeOp},
                                                              {"op", ecat::AlState::Op}};
    result.exit_code = run_cyclic(RunOptions{run->link, run->json, run->cycle_us, run->duration_s, run->dc,
                                             kStates.at(run->final_state)});
  });
}

}  // namespace sf::app
