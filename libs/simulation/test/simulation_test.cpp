// The factory in its deterministic mode: orders made end to end on the plant
// by the deployment's controllers and products, checked against the plant's
// ground truth (what was placed in which box) and the downloader's inspection.
#include "sf/simulation/simulation.hpp"

#include <cmath>
#include <cstdlib>
#include <iostream>
#include <map>
#include <set>

#include <gtest/gtest.h>

#include "sf/plant/plant.hpp"
#include "sf/simulation/run.hpp"

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

// Boxes standing in place at one station at once, the most seen at any station.
std::size_t most_boxes_at_a_station(const plant::Plant& plant) {
  std::size_t most = 0;
  const auto& layout = plant.layout();
  for (std::size_t b = 0; b < layout.belts.size(); ++b) {
    for (const auto& station : layout.belts[b].stations) {
      std::size_t n = 0;
      for (const auto& box : plant.world().boxes()) {
        n += box.belt == b && std::abs(box.s - station.at_m) <= plant::kInPlaceTolerance ? 1U : 0U;
      }
      most = std::max(most, n);
    }
  }
  return most;
}

TEST(Simulation, TwoHundredSeededOrdersAreEachMadeOnceWithTheirContent) {
  auto sim = make();
  ASSERT_TRUE(sim);
  RunOptions run;
  run.orders = 200;
  run.seed = 42;
  std::size_t crowded = 0;
  run.progress_every = 100ms;
  run.progress = [&](const RunReport&) {
    crowded = std::max(crowded, most_boxes_at_a_station(sim->plant()));
  };
  const RunReport report = run_orders(*sim, run);
  EXPECT_EQ(report.done, 200U) << report.failed << " failed, " << report.unfinished << " unfinished";
  EXPECT_FALSE(report.stalled);
  EXPECT_LE(crowded, 1U) << "two boxes stood at one station";

  // Ground truth: what the plant placed in which box, slot by slot.
  std::map<plant::BoxId, std::map<std::string, int>> contents;
  std::set<std::pair<plant::BoxId, int>> slots;
  for (const auto& e : sim->plant().world().events().entries()) {
    if (e.kind == plant::EventKind::candy_placed) {
      ++contents[e.box][e.candy];
      EXPECT_TRUE(slots.insert({e.box, e.slot}).second)
          << "box " << e.box << " slot " << e.slot << " loaded twice";
    }
  }
  std::set<std::uint16_t> final_boxes;
  for (const auto& [id, r] : sim->host().records()) {
    ASSERT_EQ(r.state, factory::OrderState::done) << id << ": " << r.failure;
    ASSERT_FALSE(r.boxes.empty()) << id;
    const std::uint16_t box = r.boxes.back();
    EXPECT_TRUE(final_boxes.insert(box).second) << "box " << box << " delivered for two orders";
    EXPECT_EQ(contents[box], r.order.counts()) << id << " in box " << box;
    ASSERT_TRUE(r.inspection) << id;
    EXPECT_EQ(r.inspection->counts, r.order.counts()) << id;
  }
  // Every box that came onto the line left it through the downloader; none fell off.
  const auto& counters = sim->plant().world().counters();
  EXPECT_EQ(counters.uploaded, counters.downloaded);
  EXPECT_EQ(counters.boxes_lost, 0U);
  EXPECT_EQ(counters.dropped, 0U);
  dump_on_failure(*sim);
}

TEST(Simulation, TheSameSeedGivesTheSameRunLineForLine) {
  SimulationOptions options;
  options.seed = 9;
  auto first = make(options);
  auto second = make(options);
  ASSERT_TRUE(first && second);
  RunOptions run;
  run.orders = 12;
  run.seed = 9;
  const RunReport a = run_orders(*first, run);
  const RunReport b = run_orders(*second, run);
  EXPECT_EQ(a.done, 12U);
  EXPECT_EQ(a.simulated, b.simulated);
  EXPECT_EQ(a.messages, b.messages);
  const auto log_a = first->log();
  const auto log_b = second->log();
  ASSERT_EQ(log_a.size(), log_b.size());
  for (std::size_t i = 0; i < log_a.size(); ++i) {
    ASSERT_EQ(log_a[i].text, log_b[i].text) << "line " << i;
  }
  EXPECT_GT(log_a.size(), 100U);
}

TEST(Simulation, ALayoutWhoseCandyNoRobotCanLoadIsRefusedAtStart) {
  line::Layout layout = *line::default_layout();
  std::erase_if(layout.dispensers, [](const line::DispenserSpec& d) { return d.candy == "toffee"; });
  for (auto& r : layout.robots) {
    std::erase_if(r.dispensers, [](const std::string& d) { return d.find("toffee") != std::string::npos; });
  }
  auto sim = Simulation::create(layout);
  ASSERT_FALSE(sim);
  EXPECT_NE(sim.error().message.find("no robot of layout 'prototype' can load toffee"), std::string::npos)
      << sim.error().message;
}

TEST(Simulation, BadOrdersAreRefusedAndNothingStarts) {
  auto sim = make();
  ASSERT_TRUE(sim);
  EXPECT_FALSE(sim->submit({"x", "small-box", {{"mint", 1}}}));
  EXPECT_FALSE(sim->submit({"x", "small-box", {{"gummy", 13}}}));
  EXPECT_FALSE(sim->submit({"", "small-box", {{"gummy", 1}}}));
  ASSERT_TRUE(sim->submit({"x", "small-box", {{"gummy", 1}}}));
  EXPECT_FALSE(sim->submit({"x", "small-box", {{"gummy", 1}}}));  // the same id again
  EXPECT_EQ(sim->host().records().size(), 1U);
}

}  // namespace
}  // namespace sf::simulation
