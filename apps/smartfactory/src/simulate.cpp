// `smartfactory simulate`: the whole factory in its deterministic mode
// (libs/simulation): plant, controllers and products in this one process on
// simulated time, a seeded stream of generated orders, progress while it
// runs and a summary at the end.
#include <cstdio>
#include <iostream>
#include <string>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "commands.hpp"
#include "sf/line/layout.hpp"
#include "sf/simulation/run.hpp"

namespace sf::app {

namespace {

constexpr const char* kHelp =
    "Run the candy-packing factory in its deterministic simulation mode: the plant, every\n"
    "shop-floor controller (the smart robot's IPC on our EtherCAT master, the gateways on their\n"
    "PLCs' Modbus registers) and the order service's products in this one process, on simulated\n"
    "time over in-memory links. A seeded stream of random orders (box type, candy types and\n"
    "quantities) is negotiated, produced and inspected; the same seed gives the same run.\n"
    "Prints progress every simulated minute (stderr) and a summary: orders done, failed and\n"
    "unfinished, lead time p50/p99, boxes per hour, Contract Net messages per order, and how\n"
    "much faster than real time it ran. Ctrl-C ends the run early with the summary so far.\n"
    "Exit: 0 when every finished order was done, 1 when one failed, 2 on bad options.";

struct Options {
  std::string layout;
  std::size_t orders = 20;
  double duration_s = 0.0;
  std::uint64_t seed = 1;
  std::size_t wip = 0;
  bool json = false;
  std::string log;
};

double seconds(std::chrono::nanoseconds d) {
  return std::chrono::duration<double>(d).count();
}

nlohmann::json to_json(const simulation::RunReport& r) {
  return {{"orders",
           {{"submitted", r.submitted},
            {"done", r.done},
            {"failed", r.failed},
            {"unfinished", r.unfinished},
            {"remade", r.remade}}},
          {"lead_time_s", {{"p50", seconds(r.lead_p50)}, {"p99", seconds(r.lead_p99)}}},
          {"boxes_per_hour", r.boxes_per_hour()},
          {"messages_per_order",
           r.done > 0 ? static_cast<double>(r.messages) / static_cast<double>(r.done) : 0.0},
          {"stalled", r.stalled},
          {"simulated_s", seconds(r.simulated)},
          {"wall_s", seconds(r.wall)},
          {"speedup", r.speedup()}};
}

void print(const simulation::RunReport& r) {
  std::cout << fmt::format(
      "orders: {} done, {} failed, {} unfinished of {} ({} boxes remade)\n"
      "lead time: p50 {:.1f} s, p99 {:.1f} s\n"
      "throughput: {:.1f} boxes/hour of simulated time\n"
      "negotiation: {:.0f} Contract Net messages per order done\n"
      "simulated {:.0f} s in {:.2f} s ({:.0f}x real time)\n",
      r.done, r.failed, r.unfinished, r.submitted, r.remade, seconds(r.lead_p50), seconds(r.lead_p99),
      r.boxes_per_hour(), r.done > 0 ? static_cast<double>(r.messages) / static_cast<double>(r.done) : 0.0,
      seconds(r.simulated), seconds(r.wall), r.speedup());
}

int run(const Options& o) {
  auto layout = o.layout.empty() ? line::default_layout() : line::load_layout(o.layout);
  if (!layout) {
    std::cerr << "simulate: " << layout.error().message << "\n";
    return kExitUsage;
  }
  simulation::SimulationOptions options;
  options.seed = o.seed;
  options.host.wip = o.wip;
  auto sim = simulation::Simulation::create(std::move(*layout), options);
  if (!sim) {
    std::cerr << "simulate: " << sim.error().message << "\n";
    return kExitUsage;
  }
  install_stop_signals();
  simulation::RunOptions run;
  run.orders = o.orders;
  run.duration =
      std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::duration<double>(o.duration_s));
  run.seed = o.seed;
  run.stop = [] { return stop_requested(); };
  // A line when an order finished since the last one, or every simulated hour.
  run.progress = [last = std::pair<std::size_t, std::size_t>{},
                  quiet = 0](const simulation::RunReport& r) mutable {
    if (std::pair(r.done, r.failed) == last && ++quiet < 60) {
      return;
    }
    last = {r.done, r.failed};
    quiet = 0;
    std::cerr << fmt::format("t={:.0f} s: {} done, {} failed, {} unfinished\n", seconds(r.simulated), r.done,
                             r.failed, r.unfinished);
  };
  const auto report = simulation::run_orders(**sim, run);
  if (!o.log.empty()) {
    std::FILE* f = std::fopen(o.log.c_str(), "w");
    if (f == nullptr) {
      std::cerr << "simulate: cannot write " << o.log << "\n";
      return kExitFailure;
    }
    for (const auto& line : (*sim)->log()) {
      std::fputs((line.text + "\n").c_str(), f);
    }
    std::fclose(f);
  }
  if (o.json) {
    std::cout << to_json(report).dump() << "\n";
  } else {
    print(report);
  }
  if (report.stalled) {
    std::cerr << "simulate: stalled: no order finished for 30 simulated minutes\n";
  }
  return report.failed == 0 && !report.stalled ? kExitOk : kExitFailure;
}

}  // namespace

void register_simulate(CLI::App& app, CommandResult& result) {
  static Options o;
  auto* cmd =
      app.add_subcommand("simulate", "The whole factory in one process on simulated time (deterministic)");
  cmd->footer(kHelp);
  cmd->add_option("--layout", o.layout, "Layout file (default: the built-in prototype line)");
  cmd->add_option("--orders", o.orders, "Finished orders to wait for (0: run for --duration)")
      ->capture_default_str();
  cmd->add_option("--duration", o.duration_s, "Simulated seconds at most (0: until --orders are finished)")
      ->check(CLI::NonNegativeNumber);
  cmd->add_option("--seed", o.seed, "Seed of the plant and the order stream")->capture_default_str();
  cmd->add_option("--wip", o.wip, "Boxes on the line at once (0: the layout's safe bound)")
      ->capture_default_str();
  cmd->add_option("--log", o.log, "Write the run's event log (orders and plant) to this file");
  cmd->add_flag("--json", o.json, "Print the summary as one JSON object");
  cmd->callback([&result] {
    if (o.orders == 0 && o.duration_s <= 0.0) {
      std::cerr << "simulate: give --orders or --duration\n";
      result.exit_code = kExitUsage;
      return;
    }
    result.exit_code = run(o);
  });
}

}  // namespace sf::app
