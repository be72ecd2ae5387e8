// The factory's deterministic mode at scale: two hundred seeded orders with
// random mixes through the default line, each checked against the plant's
// ground truth and the downloader's inspection; a repeated seed repeats the run line for line.
#include <set>

#include <gtest/gtest.h>

#include "sf/plant/plant.hpp"
#include "sf/simulation/run.hpp"
#include "simulation_checks.hpp"

namespace sf::simulation {
namespace {

using namespace std::chrono_literals;
using testing::dump_on_failure;
using testing::knowledge_alarms;
using testing::make;
using testing::most_boxes_at_a_station;

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
  // The cloud's rules over every inspection as the order service published it: no violation.
  const auto alarms = knowledge_alarms(*sim);
  EXPECT_TRUE(alarms.empty()) << alarms.size() << " alarms, the first: " << alarms.front().entity << " "
                              << alarms.front().message;
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

}  // namespace
}  // namespace sf::simulation
