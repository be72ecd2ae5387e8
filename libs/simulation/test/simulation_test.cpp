// The factory in its deterministic mode: orders made end to end on the plant
// by the deployment's controllers and products, checked against the plant's
// ground truth (what was placed in which box) and the downloader's inspection.
#include "sf/simulation/simulation.hpp"

#include <cstdlib>
#include <iostream>
#include <map>
#include <set>

#include <gtest/gtest.h>

#include "sf/plant/plant.hpp"

namespace sf::simulation {
namespace {

using namespace std::chrono_literals;

std::unique_ptr<Simulation> make(SimulationOptions options = {}) {
  auto sim = Simulation::create(*line::default_layout(), options);
  EXPECT_TRUE(sim) << sim.error().describe();
  return sim ? std::move(*sim) : nullptr;
}

// Candies placed per box, by type, from the plant's own events.
std::map<plant::BoxId, std::map<std::string, int>> placed(const plant::Plant& plant) {
  std::map<plant::BoxId, std::map<std::string, int>> out;
  for (const auto& e : plant.world().events().entries()) {
    if (e.kind == plant::EventKind::candy_placed) {
      ++out[e.box][e.candy];
    }
  }
  return out;
}

void dump_on_failure(const Simulation& sim) {
  if (::testing::Test::HasFailure() || std::getenv("SF_SIM_LOG") != nullptr) {
    for (const auto& l : sim.log()) {
      std::cerr << l.text << "\n";
    }
  }
}

TEST(Simulation, AnOrderIsUploadedLoadedInspectedAndDone) {
  auto sim = make();
  ASSERT_TRUE(sim);
  factory::Order order{"alice-1", "small-box", {{"gummy", 2}, {"toffee", 1}}};
  ASSERT_TRUE(sim->submit(order));
  EXPECT_TRUE(sim->run_until([&] { return sim->host().idle(); }, 300s));
  const auto& r = sim->host().records().at("alice-1");
  EXPECT_EQ(r.state, factory::OrderState::done) << r.failure;
  ASSERT_EQ(r.boxes.size(), 1U);
  ASSERT_TRUE(r.inspection);
  EXPECT_EQ(r.inspection->counts, order.counts());
  EXPECT_EQ(placed(sim->plant()).at(r.boxes[0]), order.counts());
  dump_on_failure(*sim);
}

}  // namespace
}  // namespace sf::simulation
