// The factory's scheduling in its deterministic mode (libs/simulation), every
// figure next to a peer measured in the same run:
//   (a) throughput (boxes per hour of simulated time) and order lead time
//       p50/p99 on the same seeded order stream for the prototype line and for
//       a line of ten of its stages (sf::line::staged_line), the Contract Net
//       next to the central dispatcher (goal ≥ 1.0× its throughput) and next
//       to the bottleneck bound, the busiest machine's time in work over the
//       run's span (goal ≥ 0.85 of the bound);
//   (b) the products' wait for decisions as a share of their time on the
//       line and Contract Net messages per order, for both lines, and
//       messages and wall time per negotiation with 10 to 100 capable
//       contractors on the in-memory network (goal: messages linear in them);
//   (c) simulation speed: simulated / wall time for ORDERS_SPEED orders on the
//       prototype line (goal ≥ 200×; the peer is the wall clock).
// Every order is submitted at the start, so lead times include the queue.
//   bench_factory [ORDERS] [ORDERS_10X] [ORDERS_SPEED]   (default 200 40 1000; 0 leaves a part out)
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "sf/core/clock.hpp"
#include "sf/line/staged_line.hpp"
#include "sf/negotiation/contractor.hpp"
#include "sf/negotiation/manager.hpp"
#include "sf/negotiation/memory_transport.hpp"
#include "sf/simulation/run.hpp"
#include "sf/simulation/simulation.hpp"

namespace {

using namespace std::chrono_literals;
using sf::simulation::Decisions;
using sf::simulation::RunReport;

constexpr std::uint64_t kSeed = 42;

double seconds(std::chrono::nanoseconds d) {
  return std::chrono::duration<double>(d).count();
}

std::optional<RunReport> run(const sf::line::Layout& layout, Decisions decisions, std::size_t orders) {
  sf::simulation::SimulationOptions options;
  options.seed = kSeed;
  options.decisions = decisions;
  options.host.wip = 0;  // the layout's safe bound
  auto sim = sf::simulation::Simulation::create(layout, options);
  if (!sim) {
    std::fprintf(stderr, "bench_factory: %s\n", sim.error().describe().c_str());
    return std::nullopt;
  }
  sf::simulation::RunOptions o;
  o.orders = orders;
  o.seed = kSeed;
  return sf::simulation::run_orders(**sim, o);
}

void print_header() {
  std::printf("%-10s %-12s %5s %7s %8s %8s %9s %-14s %6s %8s %9s %9s %7s %8s\n", "line", "decisions", "done",
              "box/h", "p50 s", "p99 s", "on line s", "bottleneck", "util", "bound/h", "msg/order",
              "deciding", "wall s", "sim/wall");
}

// "on line": a box's mean time from admission to its end; with the WIP limit it sets the pace.
void print_row(const char* line, const char* decisions, const RunReport& r) {
  const double done = static_cast<double>(r.done);
  std::printf("%-10s %-12s %5zu %7.1f %8.1f %8.1f %9.1f %-14s %6.2f %8.1f %9.1f %8.3f%% %7.1f %7.0fx\n", line,
              decisions, r.done, r.boxes_per_hour(), seconds(r.lead_p50), seconds(r.lead_p99),
              r.done > 0 ? seconds(r.on_line) / done : 0.0, r.bottleneck.c_str(), r.utilisation(),
              r.bound_boxes_per_hour(), r.done > 0 ? static_cast<double>(r.messages) / done : 0.0,
              100.0 * r.decision_share(), seconds(r.wall), r.speedup());
}

// (a) and (b) on one line: the Contract Net, then the dispatcher, then the ratios.
void compare(const char* name, const sf::line::Layout& layout, std::size_t orders) {
  const auto cnp = run(layout, Decisions::contract_net, orders);
  const auto central = run(layout, Decisions::central_dispatcher, orders);
  if (!cnp || !central) {
    return;
  }
  print_row(name, "contract-net", *cnp);
  print_row(name, "dispatcher", *central);
  const double ratio =
      central->boxes_per_hour() > 0 ? cnp->boxes_per_hour() / central->boxes_per_hour() : 0.0;
  std::printf(
      "  %s: Contract Net / dispatcher throughput %.2fx (goal >= 1.0); of its bound %.2f, the "
      "dispatcher's %.2f (goal >= 0.85)%s\n",
      name, ratio, cnp->utilisation(), central->utilisation(),
      cnp->done < orders || central->done < orders ? "; NOT ALL ORDERS DONE" : "");
}

// (b) A manager and n contractors that can all do the operation, on the in-memory network: the
// messages of one negotiation (ANNOUNCE, n BIDs, AWARD, CONFIRM, INFORM-DONE) and its wall time.
struct Scaling {
  double messages = 0;       // per negotiation
  double wall_us = 0;        // per negotiation, announce to INFORM-DONE
  double to_confirm_ms = 0;  // simulated, announce to CONFIRM
};

Scaling negotiate(std::size_t n, std::size_t negotiations) {
  namespace cnp = sf::negotiation;
  sf::ManualClock clock;
  cnp::MemoryNetwork net(clock);
  auto& products = net.add_manager();
  cnp::ManagerConfig mc;
  mc.incarnation = 1;
  cnp::Manager manager(products, clock, mc);
  products.bind(static_cast<cnp::ManagerInbox&>(manager));
  std::vector<std::unique_ptr<cnp::Contractor>> contractors;
  for (std::size_t i = 0; i < n; ++i) {
    const std::string name = fmt::format("robot-{}", i);
    auto& endpoint = net.add_contractor(name, {"load"});
    auto c = cnp::Contractor::create(endpoint, clock, {name, {{"load", 100ms, 1.0}}});
    contractors.push_back(std::make_unique<cnp::Contractor>(std::move(*c)));
    endpoint.bind(*contractors.back());
  }
  std::chrono::nanoseconds to_confirm{0};
  const auto wall = std::chrono::steady_clock::now();
  for (std::size_t k = 0; k < negotiations; ++k) {
    bool done = false;
    const auto started = clock.now();
    cnp::ConversationEvents events{[&](const cnp::Conversation&) { to_confirm += clock.now() - started; },
                                   [&](const cnp::Conversation&) { done = true; },
                                   [&](const cnp::Conversation&) { done = true; }};
    (void)manager.negotiate({"product", "load", {{"count", 1.0}}, {}}, std::move(events));
    while (!done) {
      clock.advance(1ms);
      net.deliver();
      manager.tick();
      for (auto& c : contractors) {
        c->tick();
      }
    }
  }
  const double count = static_cast<double>(negotiations);
  return {static_cast<double>(net.stats().sent) / count,
          std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - wall).count() / count,
          std::chrono::duration<double, std::milli>(to_confirm).count() / count};
}

void negotiation_scaling() {
  std::printf("\n%11s %9s %11s %13s %12s\n", "contractors", "msg/neg", "msg/neg/n", "to confirm ms",
              "wall us/neg");
  for (const std::size_t n : {10U, 20U, 50U, 100U}) {
    const Scaling s = negotiate(n, 200);
    std::printf("%11zu %9.1f %11.2f %13.2f %12.1f\n", n, s.messages, s.messages / static_cast<double>(n),
                s.to_confirm_ms, s.wall_us);
  }
}

}  // namespace

int main(int argc, char** argv) {
  const std::size_t orders = argc > 1 ? std::strtoul(argv[1], nullptr, 10) : 200;
  const std::size_t orders_10x = argc > 2 ? std::strtoul(argv[2], nullptr, 10) : 40;
  const std::size_t orders_speed = argc > 3 ? std::strtoul(argv[3], nullptr, 10) : 1000;
  std::setvbuf(stdout, nullptr, _IOLBF, 0);  // rows as they come: a run takes minutes
  auto base = sf::line::default_layout();
  auto ten = base ? sf::line::staged_line(*base, 10) : base;
  if (!base || !ten) {
    std::fprintf(stderr, "bench_factory: %s\n", (base ? ten : base).error().describe().c_str());
    return 1;
  }
  std::printf("seed %llu; %zu orders on the prototype line, %zu on ten stages of it\n",
              static_cast<unsigned long long>(kSeed), orders, orders_10x);
  print_header();
  if (orders > 0) {
    compare("prototype", *base, orders);
  }
  if (orders_10x > 0) {
    compare("10 stages", *ten, orders_10x);
  }
  negotiation_scaling();
  if (orders_speed == 0) {
    return 0;
  }
  if (const auto speed = run(*base, Decisions::contract_net, orders_speed)) {
    std::printf("\nspeed: %zu orders, %.0f s simulated in %.1f s wall: %.0fx real time (goal >= 200x)\n",
                speed->done, seconds(speed->simulated), seconds(speed->wall), speed->speedup());
  }
  return 0;
}
