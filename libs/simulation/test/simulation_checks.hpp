// What the simulation's tests check runs with: a simulation of the default
// line, the plant's ground truth (candies placed per box), boxes crowding a
// station, and the run's log printed when a test failed (or SF_SIM_LOG is set).
#pragma once

#include <cmath>
#include <cstdlib>
#include <iostream>
#include <map>
#include <memory>
#include <string>

#include <gtest/gtest.h>

#include "sf/cloud/knowledge_loop.hpp"
#include "sf/core/config.hpp"
#include "sf/plant/plant.hpp"
#include "sf/simulation/simulation.hpp"

namespace sf::simulation::testing {

inline std::unique_ptr<Simulation> make(SimulationOptions options = {}) {
  auto sim = Simulation::create(*line::default_layout(), options);
  EXPECT_TRUE(sim) << sim.error().describe();
  return sim ? std::move(*sim) : nullptr;
}

// Candies placed per box, by type, from the plant's own events.
inline std::map<plant::BoxId, std::map<std::string, int>> placed(const plant::Plant& plant) {
  std::map<plant::BoxId, std::map<std::string, int>> out;
  for (const auto& e : plant.world().events().entries()) {
    if (e.kind == plant::EventKind::candy_placed) {
      ++out[e.box][e.candy];
    }
  }
  return out;
}

// Makes one order on an idle line: done in one box whose inspection and ground truth equal it.
inline void expect_made(Simulation& sim, const factory::Order& order) {
  ASSERT_TRUE(sim.submit(order));
  EXPECT_TRUE(sim.run_until([&] { return sim.host().idle(); }, std::chrono::seconds{300}));
  const auto& r = sim.host().records().at(order.id);
  EXPECT_EQ(r.state, factory::OrderState::done) << r.failure;
  ASSERT_EQ(r.boxes.size(), 1U);
  ASSERT_TRUE(r.inspection);
  EXPECT_EQ(r.inspection->counts, order.counts());
  EXPECT_EQ(placed(sim.plant()).at(r.boxes[0]), order.counts());
}

// The cloud's check of the run: every inspection as the order service publishes it
// (OrderService.LastInspection) through the knowledge loop over the repository's ontology and
// rules (SF_SOURCE_DIR); the alarms it raised.
inline std::vector<cloud::Alarm> knowledge_alarms(const Simulation& sim) {
  const char* root = std::getenv("SF_SOURCE_DIR");  // NOLINT(concurrency-mt-unsafe): no thread sets it
  const std::string dir = root != nullptr ? root : ".";
  auto ontology = config::read_text(dir + "/ontology/candy-factory.ttl");
  auto rules = config::read_text(dir + "/rules/candy-factory.rules");
  EXPECT_TRUE(ontology && rules) << "SF_SOURCE_DIR names the repository";
  if (!ontology || !rules) {
    return {};
  }
  std::vector<cloud::Alarm> alarms;
  auto loop =
      cloud::KnowledgeLoop::create(sim.plant().layout(), {*ontology, *rules, "candy-factory.rules", {}},
                                   [&](const cloud::Alarm& a) { alarms.push_back(a); });
  EXPECT_TRUE(loop) << loop.error().describe();
  if (!loop) {
    return {};
  }
  historian::SeriesInfo series{"orders",
                               "ns=1;s=OrderService.LastInspection",
                               "/Objects/OrderService/LastInspection",
                               historian::DataType::string,
                               {}};
  for (const auto& e : sim.order_events()) {
    if (e.what != "inspected") {
      continue;
    }
    cloud::LiveUpdate u{&series, {}, false};
    u.sample.source_time =
        historian::Timestamp{} + std::chrono::duration_cast<historian::Micros>(e.at.time_since_epoch());
    u.sample.value = line::format_inspection(factory::inspection_record(e, sim.host().records().at(e.order)));
    (*loop)->on_value(u);
  }
  EXPECT_EQ((*loop)->status().rejected, 0U) << (*loop)->status().last_error;
  return alarms;
}

inline void dump_on_failure(const Simulation& sim) {
  if (::testing::Test::HasFailure() || std::getenv("SF_SIM_LOG") != nullptr) {
    for (const auto& l : sim.log()) {
      std::cerr << l.text << "\n";
    }
  }
}

// Boxes standing in place at one station at once, the most seen at any station.
inline std::size_t most_boxes_at_a_station(const plant::Plant& plant) {
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

}  // namespace sf::simulation::testing
