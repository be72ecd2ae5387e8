#include "sf/simulation/run.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

#include "sf/factory/order.hpp"
#include "sf/plant/plant.hpp"

namespace sf::simulation {

using namespace std::chrono_literals;

double RunReport::boxes_per_hour() const {
  const double hours = std::chrono::duration<double>(simulated).count() / 3600.0;
  return hours > 0.0 ? static_cast<double>(done) / hours : 0.0;
}

double RunReport::speedup() const {
  return wall.count() > 0 ? static_cast<double>(simulated.count()) / static_cast<double>(wall.count()) : 0.0;
}

double RunReport::utilisation() const {
  return simulated.count() > 0
             ? static_cast<double>(bottleneck_working.count()) / static_cast<double>(simulated.count())
             : 0.0;
}

double RunReport::bound_boxes_per_hour() const {
  const double u = utilisation();
  return u > 0.0 ? boxes_per_hour() / u : 0.0;
}

double RunReport::decision_share() const {
  return on_line.count() > 0 ? static_cast<double>(deciding.count()) / static_cast<double>(on_line.count())
                             : 0.0;
}

namespace {

// What the simulation had counted when the run began.
struct Baseline {
  Clock::time_point started;
  std::chrono::steady_clock::time_point wall;
  std::vector<MachineLoad> loads;
  std::chrono::nanoseconds deciding;
  std::chrono::nanoseconds on_line;
  static Baseline of(const Simulation& sim) {
    return {sim.now(), std::chrono::steady_clock::now(), sim.loads(), sim.deciding(), sim.on_line()};
  }
};

void bottleneck(const Simulation& sim, const Baseline& from, RunReport& r) {
  const auto loads = sim.loads();
  for (std::size_t i = 0; i < loads.size(); ++i) {
    const auto working = loads[i].working - (i < from.loads.size() ? from.loads[i].working : 0ns);
    if (working > r.bottleneck_working) {
      r.bottleneck = loads[i].machine;
      r.bottleneck_working = working;
    }
  }
}

RunReport report(const Simulation& sim, const Baseline& from) {
  RunReport r;
  for (const auto& [id, rec] : sim.host().records()) {
    ++r.submitted;
    if (rec.state == factory::OrderState::done) {
      ++r.done;
    } else if (rec.state == factory::OrderState::failed) {
      ++r.failed;
    } else {
      ++r.unfinished;
    }
  }
  r.remade = sim.host().remade();
  r.lead_p50 = sim.host().lead_time(0.5);
  r.lead_p99 = sim.host().lead_time(0.99);
  r.simulated = sim.now() - from.started;
  r.wall = std::chrono::steady_clock::now() - from.wall;
  r.messages = sim.messages();
  r.deciding = sim.deciding() - from.deciding;
  r.on_line = sim.on_line() - from.on_line;
  bottleneck(sim, from, r);
  return r;
}

}  // namespace

RunReport run_orders(Simulation& sim, const RunOptions& options) {
  factory::OrderGenerator orders(sim.plant().layout().catalog, options.seed);
  const Baseline from = Baseline::of(sim);
  const Clock::time_point started = from.started;
  const auto end = options.duration.count() > 0 ? started + options.duration : Clock::time_point::max();
  auto next_progress = started + options.progress_every;
  auto finished = [&] {
    return sim.host().count(factory::OrderState::done) + sim.host().count(factory::OrderState::failed);
  };
  // With a count, every order is in from the start; over a span, the queue is kept topped up.
  std::size_t submitted = 0;
  auto top_up = [&] {
    const std::size_t want = options.orders > 0 ? options.orders : finished() + 2 * sim.host().wip();
    for (; submitted < want; ++submitted) {
      (void)sim.submit(orders.next());
    }
  };
  std::size_t last_finished = 0;
  Clock::time_point last_change = started;
  bool stalled = false;
  while (sim.now() < end && (options.orders == 0 || finished() < options.orders)) {
    if (options.stop && options.stop()) {
      break;
    }
    if (const std::size_t f = finished(); f != last_finished) {
      last_finished = f;
      last_change = sim.now();
    } else if (sim.now() - last_change > options.stall_after) {
      stalled = true;
      break;
    }
    top_up();
    sim.step();
    if (options.progress && sim.now() >= next_progress) {
      next_progress += options.progress_every;
      options.progress(report(sim, from));
    }
  }
  RunReport r = report(sim, from);
  r.stalled = stalled;
  return r;
}

}  // namespace sf::simulation
