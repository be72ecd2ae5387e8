// The factory in its deterministic mode: orders made end to end on the plant
// by the deployment's controllers and products, checked against the plant's
// ground truth (what was placed in which box) and the downloader's inspection.
#include "sf/simulation/simulation.hpp"

#include <cmath>
#include <cstdlib>
#include <iostream>
#include <map>
#include <set>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "sf/plant/plant.hpp"
#include "sf/simulation/run.hpp"
#include "simulation_checks.hpp"

namespace sf::simulation {
namespace {

using namespace std::chrono_literals;
using testing::dump_on_failure;
using testing::expect_made;
using testing::knowledge_alarms;
using testing::make;
using testing::placed;

TEST(Simulation, AnOrderIsUploadedLoadedInspectedAndDone) {
  auto sim = make();
  ASSERT_TRUE(sim);
  expect_made(*sim, {"alice-1", "small-box", {{"gummy", 2}, {"toffee", 1}}});
  dump_on_failure(*sim);
}

// Every order of the host done, its last box holding what it asked for (the plant's ground truth).
void expect_all_done_with_their_content(const Simulation& sim) {
  const auto contents = placed(sim.plant());
  for (const auto& [id, r] : sim.host().records()) {
    EXPECT_EQ(r.state, factory::OrderState::done) << id << ": " << r.failure;
    ASSERT_FALSE(r.boxes.empty()) << id;
    const auto it = contents.find(r.boxes.back());
    EXPECT_TRUE(it != contents.end() && it->second == r.order.counts()) << id << " in box " << r.boxes.back();
  }
}

bool placed_by(const Simulation& sim, std::string_view robot) {
  for (const auto& e : sim.plant().world().events().entries()) {
    if (e.kind == plant::EventKind::candy_placed && e.where == robot) {
      return true;
    }
  }
  return false;
}

TEST(SimulationFaults, ASmartRobotKilledMidLoadIsReplacedAndItsBoxFinishedOrMadeAgain) {
  auto sim = make();
  ASSERT_TRUE(sim);
  // Chocolate and gummy: SCARA Robot 1 has both; DENSO (chocolate) and TOSHIBA (gummy) too.
  ASSERT_TRUE(sim->submit({"a", "small-box", {{"chocolate", 4}, {"gummy", 3}}}));
  ASSERT_TRUE(sim->submit({"b", "small-box", {{"gummy", 4}}}));
  ASSERT_TRUE(sim->run_until([&] { return placed_by(*sim, "scara-robot-1"); }, 600s));
  ASSERT_TRUE(sim->kill("scara-robot-1"));
  EXPECT_TRUE(sim->run_until([&] { return sim->host().idle(); }, 3600s));
  expect_all_done_with_their_content(*sim);
  bool renegotiated = false;
  for (const auto& e : sim->order_events()) {
    renegotiated = renegotiated || (e.what == "awarded" && e.machine != "scara-robot-1" &&
                                    e.detail.starts_with("load") && e.at > sim->now() - 3600s);
  }
  EXPECT_TRUE(renegotiated);
  EXPECT_FALSE(sim->kill("no-such-machine"));
  dump_on_failure(*sim);
}

std::chrono::nanoseconds working(const Simulation& sim, std::string_view machine) {
  for (const auto& l : sim.loads()) {
    if (l.machine == machine) {
      return l.working;
    }
  }
  return {};
}

// SCARA Robot 1's DDS link cut for 5 s while it loads a box. The order service loses it after the
// lease and negotiates the load again after kLostGrace; the robot finishes the load meanwhile, and
// its INFORM-DONE arrives once the link is back: the load is done, and the machine it went to in
// the meantime is told to stop. No box is loaded twice (no candy dropped onto a filled slot), none
// is made again.
TEST(SimulationFaults, ASmartRobotCutOffWhileLoadingLoadsItsBoxOnce) {
  auto sim = make();
  ASSERT_TRUE(sim);
  const std::vector<factory::Order> orders{{"a", "small-box", {{"gummy", 1}}},
                                           {"b", "small-box", {{"chocolate", 1}}},
                                           {"c", "small-box", {{"gummy", 1}, {"chocolate", 1}}}};
  for (const auto& o : orders) {
    ASSERT_TRUE(sim->submit(o));
  }
  ASSERT_TRUE(sim->run_until([&] { return working(*sim, "scara-robot-1") > 0ns; }, 600s));
  std::string cut_order;  // whose load the robot has in work
  for (const auto& e : sim->order_events()) {
    if (e.what == "awarded" && e.machine == "scara-robot-1") {
      cut_order = e.order;
    }
  }
  ASSERT_TRUE(sim->cut_off("scara-robot-1"));
  const auto cut_at = sim->now();
  sim->run_until([] { return false; }, 5s);
  ASSERT_TRUE(sim->reconnect("scara-robot-1"));
  EXPECT_FALSE(sim->cut_off("no-such-machine"));
  EXPECT_TRUE(sim->run_until([&] { return sim->host().idle(); }, 3600s));
  expect_all_done_with_their_content(*sim);

  // The partition did what it should: the load was negotiated again while the robot was away,
  // and the robot's own report of it counted.
  bool renegotiated = false;
  bool loaded_by_robot = false;
  for (const auto& e : sim->order_events()) {
    if (e.order == cut_order && e.at > cut_at) {
      renegotiated = renegotiated || (e.what == "awarded" && e.detail.starts_with("load (round 2"));
      loaded_by_robot = loaded_by_robot || (e.what == "loaded" && e.machine == "scara-robot-1");
    }
  }
  EXPECT_TRUE(renegotiated) << cut_order;
  EXPECT_TRUE(loaded_by_robot) << cut_order;
  const auto& counters = sim->plant().world().counters();
  EXPECT_EQ(counters.dropped, 0U);
  EXPECT_EQ(counters.uploaded, orders.size());
  EXPECT_EQ(counters.placed, 4U);
  for (const auto& [id, r] : sim->host().records()) {
    EXPECT_EQ(r.boxes.size(), 1U) << id << " made again";
  }
  dump_on_failure(*sim);
}

TEST(SimulationFaults, APlcUnreachableIsWaitedForAndTheLineGoesOnWhenItReturns) {
  auto sim = make();
  ASSERT_TRUE(sim);
  // Toffee only at the TOSHIBA, on conveyor 3: its conveyor's PLC away for a minute.
  ASSERT_TRUE(sim->submit({"a", "small-box", {{"toffee", 2}}}));
  ASSERT_TRUE(sim->submit({"b", "small-box", {{"chocolate", 2}}}));
  ASSERT_TRUE(sim->inject("plc-unreachable:conveyor3"));
  sim->run_until([] { return false; }, 60s);
  EXPECT_EQ(sim->host().records().at("a").state, factory::OrderState::in_work);
  ASSERT_TRUE(sim->clear("plc-unreachable:conveyor3"));
  EXPECT_TRUE(sim->run_until([&] { return sim->host().idle(); }, 3600s));
  expect_all_done_with_their_content(*sim);
  dump_on_failure(*sim);
}

// The first event `what` of an order, if any.
const factory::OrderEvent* first_event(const Simulation& sim, std::string_view order, std::string_view what) {
  for (const auto& e : sim.order_events()) {
    if (e.order == order && e.what == what) {
      return &e;
    }
  }
  return nullptr;
}

// The downloader's inspection of a box as the plant recorded it ("weight=…g candy=n …").
std::string plant_inspection(const Simulation& sim, plant::BoxId box) {
  for (const auto& e : sim.plant().world().events().entries()) {
    if (e.kind == plant::EventKind::box_inspected && e.box == box) {
      return e.detail;
    }
  }
  return {};
}

TEST(SimulationFaults, ABoxWithTheWrongCandyIsRejectedAndTheOrderMadeAgain) {
  auto sim = make();
  ASSERT_TRUE(sim);
  // Toffee only at the TOSHIBA; its toffee dispenser refilled with the catalog's next candy, chocolate.
  ASSERT_TRUE(sim->inject("mixup:toshiba-toffee"));
  ASSERT_TRUE(sim->submit({"a", "small-box", {{"toffee", 2}}}));
  ASSERT_TRUE(sim->run_until([&] { return first_event(*sim, "a", "rejected") != nullptr; }, 600s));
  ASSERT_TRUE(sim->clear("mixup:toshiba-toffee"));
  EXPECT_TRUE(sim->run_until([&] { return sim->host().idle(); }, 3600s));

  const auto& r = sim->host().records().at("a");
  EXPECT_EQ(r.state, factory::OrderState::done) << r.failure;
  EXPECT_EQ(r.attempts, 2U);
  EXPECT_EQ(sim->host().remade(), 1U);
  ASSERT_EQ(r.boxes.size(), 2U);
  const auto contents = placed(sim->plant());
  EXPECT_EQ(contents.at(r.boxes[0]), (std::map<std::string, int>{{"chocolate", 2}}));
  EXPECT_EQ(contents.at(r.boxes[1]), r.order.counts());
  ASSERT_TRUE(r.inspection);
  EXPECT_EQ(r.inspection->box, r.boxes[1]);
  EXPECT_EQ(r.inspection->counts, r.order.counts());
  // The first box: inspected with the wrong candy and rejected for it, before the order was made again.
  EXPECT_EQ(plant_inspection(*sim, r.boxes[0]), "weight=65.0g chocolate=2");
  const auto* rejected = first_event(*sim, "a", "rejected");
  ASSERT_NE(rejected, nullptr);
  EXPECT_EQ(rejected->detail,
            fmt::format("content mismatch in box {}: 2 chocolate of 0, 0 toffee of 2", r.boxes[0]));
  const auto* remade = first_event(*sim, "a", "remade");
  ASSERT_NE(remade, nullptr);
  EXPECT_GE(remade->at, rejected->at);
  std::size_t rejects = 0;
  for (const auto& e : sim->order_events()) {
    rejects += e.order == "a" && e.what == "rejected" ? 1U : 0U;
  }
  EXPECT_EQ(rejects, 1U);
  // The cloud's rules find the same, independently of the order service's own comparison, for
  // the first box only: the toffee missing, the chocolate not ordered.
  std::set<std::string> alarms;
  for (const auto& a : knowledge_alarms(*sim)) {
    EXPECT_TRUE(a.entity.ends_with(fmt::format("Box_a_{}", r.boxes[0]))) << a.entity;
    alarms.insert(a.rule + ": " + a.message);
  }
  EXPECT_EQ(alarms, (std::set<std::string>{"contentMismatch: toffee: ordered 2, the box holds 0",
                                           "contentMismatch: chocolate: ordered 0, the box holds 2"}));
  dump_on_failure(*sim);
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
