// Lines of several stages of the prototype (sf::line::staged_line) run as the
// prototype does: the plant and a controller for every machine come up, and
// an order is made with its content.
#include "sf/line/staged_line.hpp"

#include <gtest/gtest.h>

#include "sf/simulation/simulation.hpp"
#include "simulation_checks.hpp"

namespace sf::simulation {
namespace {

using testing::dump_on_failure;
using testing::expect_made;

TEST(StagedLineSimulation, TenStagesComeUpWithAControllerForEveryMachine) {
  auto layout = line::staged_line(*line::default_layout(), 10);
  ASSERT_TRUE(layout) << layout.error().describe();
  const std::size_t machines = layout->belts.size() + layout->robots.size() + 2;  // + uploader, downloader
  EXPECT_EQ(machines, 64U);
  auto sim = Simulation::create(std::move(*layout));
  ASSERT_TRUE(sim) << sim.error().describe();
  EXPECT_EQ((*sim)->loads().size(), machines);
}

TEST(StagedLineSimulation, AnOrderIsMadeOnThreeStages) {
  auto layout = line::staged_line(*line::default_layout(), 3);
  ASSERT_TRUE(layout) << layout.error().describe();
  auto sim = Simulation::create(std::move(*layout));
  ASSERT_TRUE(sim) << sim.error().describe();
  expect_made(**sim, {"carol-1", "large-box", {{"chocolate", 3}, {"toffee", 2}, {"lollipop", 1}}});
  dump_on_failure(**sim);
}

}  // namespace
}  // namespace sf::simulation
