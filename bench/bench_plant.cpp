// The plant simulation:
//   - its pace on a ManualClock: simulated seconds per wall second for the
//     default line with 20 boxes in flight (goal ≥ 200×) and for a line ten
//     times larger, every controller's program and every hardware face
//     running (the peer is the wall clock itself: the figure is the ratio to
//     real time); memory per box and per machine from the heap;
//   - the Modbus TCP round trip of a conveyor PLC with the running world
//     behind it (the plant's physics loop shares its lock) next to a bare
//     libmodbus server over the same registers, in the same run (goal ≤ 1.2×).
//   bench_plant [SIMULATED_SECONDS] [MODBUS_REQUESTS]
#include <malloc.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <string>

#include <fmt/format.h>

#include "modbus_bench.hpp"
#include "sf/core/clock.hpp"
#include "sf/plant/host.hpp"
#include "sf/plant/plant.hpp"

namespace {

using namespace std::chrono_literals;
using sf::plant::Layout;

std::size_t heap_in_use() {
  return mallinfo2().uordblks;
}

// `copies` copies of the line side by side, 6 m apart; names get "-N".
Layout replicate(const Layout& base, int copies) {
  Layout out = base;
  for (int i = 1; i < copies; ++i) {
    const std::string suffix = fmt::format("-{}", i);
    const double dy = 6.0 * i;
    for (auto belt : base.belts) {
      belt.name += suffix;
      for (auto& p : belt.path) {
        p.y += dy;
      }
      for (auto& next : belt.next) {
        next += suffix;
      }
      out.belts.push_back(std::move(belt));
    }
    for (auto d : base.dispensers) {
      d.name += suffix;
      d.at.y += dy;
      out.dispensers.push_back(std::move(d));
    }
    for (auto r : base.robots) {
      r.name += suffix;
      r.scara.base.y += dy;
      r.articulated.base.y += dy;
      for (auto& s : r.stations) {
        s.insert(s.find('/'), suffix);
      }
      for (auto& d : r.dispensers) {
        d += suffix;
      }
      out.robots.push_back(std::move(r));
    }
  }
  return out;
}

struct Figures {
  double pace = 0;  // simulated s per wall s
  std::size_t boxes = 0;
  std::size_t machines = 0;
  double bytes_per_machine = 0;
  double bytes_per_box = 0;
};

// Every belt running (the loop conveyor1 → 2 → 4 → 5 → 1 of each copy),
// `per_line` boxes put at each copy's upload station half a second apart.
Figures run(const Layout& layout, int copies, int per_line, double seconds) {
  sf::ManualClock clock;
  const std::size_t before = heap_in_use();
  auto plant = std::make_unique<sf::plant::Plant>(layout, clock);
  Figures f;
  f.machines = plant->plcs().size() + plant->smart_robots().size();
  f.bytes_per_machine = static_cast<double>(heap_in_use() - before) / static_cast<double>(f.machines);
  sf::plant::World& world = plant->world();
  for (const auto& plc : plant->plcs()) {
    if (layout.belt(plc->name()) != nullptr) {
      std::lock_guard lock(plc->mutex());
      plc->bank().set_coil(sf::plant::conveyor_plc::kMotorRun, true);
    }
  }
  const auto upload = *sf::plant::find_station(layout, layout.uploader.station);
  const std::size_t boxes_before = heap_in_use();
  for (int n = 0; n < per_line; ++n) {
    for (int i = 0; i < copies; ++i) {
      sf::plant::StationRef at = upload;
      at.belt += static_cast<std::size_t>(i) * (layout.belts.size() / static_cast<std::size_t>(copies));
      (void)world.place_box(static_cast<std::size_t>(n % 2), at, "bench");
    }
    clock.advance(500ms);
    plant->advance_to(clock.now());
  }
  f.boxes = world.boxes().size();
  f.bytes_per_box = static_cast<double>(heap_in_use() - boxes_before) /
                    static_cast<double>(std::max<std::size_t>(f.boxes, 1));
  const auto sim_start = clock.now();
  const auto wall_start = std::chrono::steady_clock::now();
  const auto end =
      sim_start + std::chrono::duration_cast<sf::Clock::duration>(std::chrono::duration<double>(seconds));
  while (clock.now() < end) {
    clock.advance(sf::plant::kWorldStep);
    plant->advance_to(clock.now());
  }
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
  f.pace = seconds / wall;
  return f;
}

void print(const char* name, const Figures& f, double goal) {
  const std::string target = goal > 0 ? fmt::format("(goal >= {:.0f})", goal) : std::string(15, ' ');
  std::printf("%-28s %5zu machines %5zu boxes  %8.0f sim s / wall s %s  %6.0f B/machine  %5.0f B/box\n", name,
              f.machines, f.boxes, f.pace, target.c_str(), f.bytes_per_machine, f.bytes_per_box);
}

// A conveyor PLC of a plant running in real time (its physics loop scanning
// the PLC every millisecond under the device's lock) against the bare server.
int modbus_round_trip(const Layout& layout, std::size_t requests) {
  sf::SteadyClock clock;
  sf::plant::Plant plant(layout, clock);
  sf::plant::HostOptions options;
  options.ecat_port = 0;
  auto host = sf::plant::PlantHost::start(plant, clock, options);
  if (!host) {
    std::fprintf(stderr, "bench_plant: %s\n", host.error().message.c_str());
    return 1;
  }
  using sf::modbus::Client;
  bool motor = false;
  const std::vector<modbus_bench::Operation> operations{
      {"read 32 inputs (eyes, jam)", [](Client& c) { return c.read_discrete_inputs(0, 32).ok(); }},
      {"read 32 input registers", [](Client& c) { return c.read_input_registers(0, 32).ok(); }},
      {"write 1 coil (motor)", [&motor](Client& c) { return c.write_single_coil(0, motor = !motor).ok(); }},
  };
  modbus_bench::Options o;
  o.requests = requests;
  std::printf(
      "\nModbus TCP round trip of conveyor2's PLC (the world behind it, physics at 1 kHz), one client, "
      "%zu requests per server and kind\n",
      o.requests);
  const auto rows = modbus_bench::compare(*plant.plc("conveyor2"), operations, o);
  if (rows.empty()) {
    return 1;
  }
  modbus_bench::print(rows);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  const double seconds = argc > 1 ? std::atof(argv[1]) : 60.0;
  auto layout = sf::plant::default_layout();
  if (!layout) {
    std::fprintf(stderr, "bench_plant: %s\n", layout.error().message.c_str());
    return 1;
  }
  std::printf("bench_plant: %.0f simulated seconds per run, 1 ms steps, every controller scanned each step\n",
              seconds);
  print("default line, 20 boxes", run(*layout, 1, 20, seconds), 200);
  print("10x line, 200 boxes", run(replicate(*layout, 10), 10, 20, seconds / 10), 0);
  return modbus_round_trip(*layout, argc > 2 ? std::strtoul(argv[2], nullptr, 10) : 20000);
}
