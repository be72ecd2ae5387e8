// A run of the deterministic factory: a stream of generated orders through a
// Simulation until N are finished or a span of simulated time is over, and
// what came of it (the figures `smartfactory simulate` prints and the
// scheduling benchmarks compare).
#pragma once

#include <chrono>
#include <cstdint>
#include <functional>
#include <string>

#include "sf/simulation/simulation.hpp"

namespace sf::simulation {

struct RunReport {
  std::size_t submitted = 0;
  std::size_t done = 0;
  std::size_t failed = 0;
  std::size_t unfinished = 0;  // queued or in work at the end
  std::uint64_t remade = 0;    // boxes made again (content mismatch, a step that found no machine)
  std::chrono::nanoseconds lead_p50{0};
  std::chrono::nanoseconds lead_p99{0};
  std::chrono::nanoseconds simulated{0};
  std::chrono::nanoseconds wall{0};
  std::uint64_t messages = 0;  // Contract Net messages, both domains
  bool stalled = false;        // ended because no order finished for RunOptions::stall_after
  // The busiest machine of the run and its time in work: with it busy all the time the line
  // could make boxes_per_hour() / utilisation at most (the bottleneck bound).
  std::string bottleneck;
  std::chrono::nanoseconds bottleneck_working{0};
  // Products' waits for decisions and their time on the line, summed (Simulation::deciding).
  std::chrono::nanoseconds deciding{0};
  std::chrono::nanoseconds on_line{0};
  [[nodiscard]] double boxes_per_hour() const;
  [[nodiscard]] double speedup() const;  // simulated time / wall time
  // The bottleneck's time in work over the run's span: the throughput as a share of the bound.
  [[nodiscard]] double utilisation() const;
  [[nodiscard]] double bound_boxes_per_hour() const;
  [[nodiscard]] double decision_share() const;  // of the products' time on the line
};

struct RunOptions {
  std::size_t orders = 20;              // finished orders to wait for; 0: until `duration`
  std::chrono::nanoseconds duration{};  // simulated; 0: until `orders` are finished
  std::uint64_t seed = 1;               // of the order stream
  // Called every `progress_every` of simulated time with the report so far.
  std::function<void(const RunReport&)> progress;
  std::chrono::nanoseconds progress_every{std::chrono::seconds{60}};
  // No order finished for this long (simulated) while some are in work: the run ends, stalled.
  std::chrono::nanoseconds stall_after{std::chrono::minutes{30}};
  // Asked between steps: true ends the run early (Ctrl-C).
  std::function<bool()> stop;
};

RunReport run_orders(Simulation& simulation, const RunOptions& options);

}  // namespace sf::simulation
