#include "sf/plant/world.hpp"

#include <cmath>

#include <gtest/gtest.h>

namespace sf::plant {
namespace {

using namespace std::chrono_literals;

class WorldTest : public ::testing::Test {
 protected:
  WorldTest() : world_(*default_layout()) {}

  std::size_t belt(std::string_view name) { return *world_.layout().belt_index(name); }
  StationRef station(std::string_view ref) { return *find_station(world_.layout(), ref); }
  BoxId put(std::string_view at, std::size_t type = 0) {
    auto id = world_.place_box(type, station(at), "test");
    EXPECT_TRUE(id) << id.error().describe();
    return id ? *id : 0;
  }
  // No two boxes on one belt overlap.
  void expect_no_overlap() {
    const auto& boxes = world_.boxes();
    for (std::size_t i = 0; i < boxes.size(); ++i) {
      for (std::size_t j = i + 1; j < boxes.size(); ++j) {
        if (boxes[i].belt != boxes[j].belt) {
          continue;
        }
        const double gap = std::abs(boxes[i].s - boxes[j].s);
        const double need = (world_.layout().catalog.box_types[boxes[i].type].size_m.x +
                             world_.layout().catalog.box_types[boxes[j].type].size_m.x) /
                            2.0;
        EXPECT_GE(gap, need - 1e-9) << "boxes " << boxes[i].id << " and " << boxes[j].id;
      }
    }
  }
  World world_;
};

TEST_F(WorldTest, ABoxRidesOntoTheNextBeltAndStopsAtARaisedStopper) {
  const BoxId id = put("conveyor1/upload");
  world_.set_stopper(belt("conveyor2"), 0, true);
  world_.set_motor(belt("conveyor1"), true, false);
  world_.set_motor(belt("conveyor2"), true, false);
  world_.advance(10s);
  const Box* box = world_.box(id);
  ASSERT_NE(box, nullptr);
  EXPECT_EQ(box->belt, belt("conveyor2"));
  EXPECT_NEAR(box->s, 1.5, 1e-9);
  EXPECT_EQ(world_.box_in_place(belt("conveyor2"), 0), box);
  EXPECT_TRUE(world_.station_eye(belt("conveyor2"), 0));
  // The log tells the story: uploaded, left the upload station, crossed, arrived.
  std::vector<EventKind> kinds;
  for (const auto& e : world_.events().entries()) {
    kinds.push_back(e.kind);
  }
  EXPECT_EQ(kinds, (std::vector<EventKind>{EventKind::box_uploaded, EventKind::box_entered_station,
                                           EventKind::box_left_station, EventKind::box_transferred,
                                           EventKind::box_entered_station}));
  EXPECT_EQ(world_.events().entries().back().where, "conveyor2/scara1");
  // Speed: 0.5 m/s over 1.7 m + 1.5 m.
  EXPECT_NEAR(std::chrono::duration<double>(world_.events().entries().back().at).count(), 3.2 / 0.5, 0.01);
}

TEST_F(WorldTest, TheDiverterSendsABoxDownTheOtherBelt) {
  const BoxId id = put("conveyor1/upload");
  world_.set_exit(belt("conveyor1"), 1);
  world_.set_motor(belt("conveyor1"), true, false);
  world_.advance(4s);
  EXPECT_EQ(world_.box(id)->belt, belt("conveyor3"));
}

TEST_F(WorldTest, ABoxAtABlockedExitWaitsAndTheNextQueuesBehindIt) {
  // conveyor2 stands still with a box on its entry: conveyor1's boxes cannot cross.
  const BoxId blocker = put("conveyor1/upload");
  world_.set_motor(belt("conveyor1"), true, false);
  world_.advance(3600ms);  // across the end, 0.1 m onto conveyor2
  ASSERT_EQ(world_.box(blocker)->belt, belt("conveyor2"));
  const BoxId first = put("conveyor1/upload");
  world_.advance(1s);
  const BoxId second = put("conveyor1/upload");
  world_.advance(20s);
  expect_no_overlap();
  ASSERT_NE(world_.box(first), nullptr);
  ASSERT_NE(world_.box(second), nullptr);
  EXPECT_EQ(world_.box(first)->belt, belt("conveyor1"));
  EXPECT_NEAR(world_.box(first)->s, 2.0 - 0.08, 1e-9);          // held at the end, wholly on its belt
  EXPECT_NEAR(world_.box(second)->s, 2.0 - 0.08 - 0.16, 1e-9);  // queued behind it
  EXPECT_TRUE(world_.exit_eye(belt("conveyor1")));
  EXPECT_EQ(world_.boxes().size(), 3U);  // none lost
  // Once conveyor2 moves, both follow.
  world_.set_motor(belt("conveyor2"), true, false);
  world_.advance(2s);
  expect_no_overlap();
  EXPECT_EQ(world_.box(first)->belt, belt("conveyor2"));
}

TEST_F(WorldTest, BoxesFromTwoBeltsMergeOneAtATime) {
  world_.set_motor(belt("conveyor1"), true, false);
  const BoxId a = put("conveyor1/upload");
  world_.advance(3500ms);
  ASSERT_EQ(world_.box(a)->belt, belt("conveyor2"));
  world_.set_exit(belt("conveyor1"), 1);
  const BoxId b = put("conveyor1/upload");
  world_.advance(3500ms);
  ASSERT_EQ(world_.box(b)->belt, belt("conveyor3"));
  world_.set_motor(belt("conveyor1"), false, false);
  world_.set_motor(belt("conveyor2"), true, false);
  world_.set_motor(belt("conveyor3"), true, false);
  world_.advance(20s);
  // conveyor4 stands: the first box has crossed onto it and blocks the merge,
  // the second waits wholly on its own belt.
  EXPECT_EQ(world_.box(a)->belt, belt("conveyor4"));
  EXPECT_LT(world_.box(a)->s, 0.01);
  EXPECT_EQ(world_.box(b)->belt, belt("conveyor3"));
  EXPECT_NEAR(world_.box(b)->s, world_.layout().belt("conveyor3")->length() - 0.08, 1e-9);
  world_.set_motor(belt("conveyor4"), true, false);
  world_.advance(2s);
  EXPECT_EQ(world_.box(b)->belt, belt("conveyor4"));
  expect_no_overlap();
  EXPECT_EQ(world_.boxes().size(), 2U);
}

TEST_F(WorldTest, AJammedBeltHoldsItsBoxesAndItsExitEyeIsStuck) {
  const BoxId id = put("conveyor1/upload");
  world_.set_jam(belt("conveyor1"), true);
  world_.set_motor(belt("conveyor1"), true, false);
  world_.advance(2s);
  EXPECT_NEAR(world_.box(id)->s, 0.3, 1e-12);
  EXPECT_TRUE(world_.exit_eye(belt("conveyor1")));
  EXPECT_GT(world_.belt(belt("conveyor1")).odometer_m, 0.9);  // the belt runs under the box
  world_.set_jam(belt("conveyor1"), false);
  EXPECT_FALSE(world_.exit_eye(belt("conveyor1")));
  world_.advance(1s);
  EXPECT_NEAR(world_.box(id)->s, 0.8, 1e-9);
}

TEST_F(WorldTest, InReverseABoxStopsAtTheEntry) {
  const BoxId id = put("conveyor1/upload");
  world_.set_motor(belt("conveyor1"), true, true);
  world_.advance(2s);
  EXPECT_EQ(world_.box(id)->belt, belt("conveyor1"));
  EXPECT_NEAR(world_.box(id)->s, 0.08, 1e-9);
  EXPECT_TRUE(world_.entry_eye(belt("conveyor1")));
}

TEST_F(WorldTest, APlaceAlreadyTakenIsRefused) {
  put("conveyor1/upload");
  auto again = world_.place_box(0, station("conveyor1/upload"), "test");
  ASSERT_FALSE(again);
  EXPECT_NE(again.error().message.find("occupied"), std::string::npos);
}

class ToolTest : public WorldTest {
 protected:
  std::size_t robot(std::string_view name) {
    const auto& robots = world_.layout().robots;
    return static_cast<std::size_t>(world_.layout().robot(name) - robots.data());
  }
  void tool_at(std::size_t r, motion::Vec3 p) { world_.set_tool(r, motion::ToolPose{p, 0.0}); }
  motion::Vec3 dispenser(std::string_view name) { return world_.layout().dispenser(name)->at; }
};

TEST_F(ToolTest, APickWithinToleranceTakesACandyAndAPlaceOverASlotFillsIt) {
  const BoxId id = put("conveyor2/scara1");
  const std::size_t r = robot("scara-robot-1");
  tool_at(r, dispenser("scara1-gummy") + motion::Vec3{0.003, -0.002, 0.001});
  world_.set_gripper(r, true);
  EXPECT_EQ(world_.tool(r).held, static_cast<int>(*world_.layout().catalog.candy_index("gummy")));
  EXPECT_EQ(world_.stock(1), 399);
  const motion::Vec3 slot = world_.slot_position(*world_.box(id), 5);
  tool_at(r, slot + motion::Vec3{0.002, 0.0, 0.01});
  world_.set_gripper(r, false);
  EXPECT_EQ(world_.box(id)->slots[5], static_cast<int>(*world_.layout().catalog.candy_index("gummy")));
  EXPECT_EQ(world_.counters().placed, 1U);
  EXPECT_EQ(world_.events().entries().back().kind, EventKind::candy_placed);
  EXPECT_EQ(world_.events().entries().back().slot, 5);
}

TEST_F(ToolTest, APickOutsideTolerancePicksNothing) {
  const std::size_t r = robot("scara-robot-1");
  tool_at(r, dispenser("scara1-gummy") + motion::Vec3{0.008, 0.0, 0.0});
  world_.set_gripper(r, true);
  EXPECT_EQ(world_.tool(r).held, -1);
  EXPECT_EQ(world_.stock(1), 400);
  EXPECT_EQ(world_.counters().pick_missed, 1U);
  EXPECT_EQ(world_.events().entries().back().kind, EventKind::pick_missed);
}

TEST_F(ToolTest, OpeningOverTheBeltDropsTheCandy) {
  put("conveyor2/scara1");
  const std::size_t r = robot("scara-robot-1");
  tool_at(r, dispenser("scara1-chocolate"));
  world_.set_gripper(r, true);
  ASSERT_GE(world_.tool(r).held, 0);
  tool_at(r, motion::Vec3{3.5, 0.12, 0.85});  // beside the box, over the belt
  world_.set_gripper(r, false);
  EXPECT_EQ(world_.tool(r).held, -1);
  EXPECT_EQ(world_.counters().dropped, 1U);
  EXPECT_EQ(world_.counters().placed, 0U);
  EXPECT_EQ(world_.events().entries().back().kind, EventKind::candy_dropped);
}

TEST_F(ToolTest, ASecondCandyIntoAFilledSlotIsDropped) {
  const BoxId id = put("conveyor2/scara1");
  const std::size_t r = robot("scara-robot-1");
  const motion::Vec3 slot = world_.slot_position(*world_.box(id), 0) + motion::Vec3{0.0, 0.0, 0.01};
  for (int i = 0; i < 2; ++i) {
    tool_at(r, dispenser("scara1-chocolate"));
    world_.set_gripper(r, true);
    tool_at(r, slot);
    world_.set_gripper(r, false);
  }
  EXPECT_EQ(world_.counters().placed, 1U);
  EXPECT_EQ(world_.counters().dropped, 1U);
  EXPECT_EQ(world_.events().entries().back().detail, "slot already filled");
}

TEST_F(ToolTest, AnEmptyDispenserGivesNothing) {
  const std::size_t r = robot("scara-robot-1");
  world_.set_stock(0, 0);
  tool_at(r, dispenser("scara1-chocolate"));
  world_.set_gripper(r, true);
  EXPECT_EQ(world_.tool(r).held, -1);
  EXPECT_EQ(world_.events().entries().back().detail, "scara1-chocolate is empty");
}

TEST_F(ToolTest, AMixedUpDispenserGivesTheCatalogsNextCandyUntilRestored) {
  const BoxId id = put("conveyor2/scara1");
  const std::size_t r = robot("scara-robot-1");
  const auto& catalog = world_.layout().catalog;
  const std::size_t d = 1;  // scara1-gummy
  ASSERT_EQ(world_.layout().dispensers[d].name, "scara1-gummy");
  world_.set_mixup(d, true);
  EXPECT_TRUE(world_.mixed_up(d));
  EXPECT_EQ(world_.events().entries().back().kind, EventKind::fault_raised);
  EXPECT_EQ(world_.events().entries().back().candy, "lollipop");
  tool_at(r, dispenser("scara1-gummy"));
  world_.set_gripper(r, true);
  EXPECT_EQ(world_.tool(r).held, static_cast<int>(*catalog.candy_index("lollipop")));  // gummy's next
  EXPECT_EQ(world_.events().entries().back().kind, EventKind::candy_picked);
  EXPECT_EQ(world_.events().entries().back().candy, "lollipop");
  EXPECT_EQ(world_.stock(d), 399);
  tool_at(r, world_.slot_position(*world_.box(id), 0) + motion::Vec3{0.0, 0.0, 0.01});
  world_.set_gripper(r, false);
  EXPECT_EQ(world_.box(id)->slots[0], static_cast<int>(*catalog.candy_index("lollipop")));
  EXPECT_EQ(world_.events().entries().back().candy, "lollipop");

  world_.set_mixup(d, false);
  EXPECT_EQ(world_.events().entries().back().kind, EventKind::fault_cleared);
  tool_at(r, dispenser("scara1-gummy"));
  world_.set_gripper(r, true);
  EXPECT_EQ(world_.tool(r).held, static_cast<int>(*catalog.candy_index("gummy")));
  // The other dispensers were never mixed up.
  EXPECT_FALSE(world_.mixed_up(0));
  EXPECT_EQ(world_.dispensed_candy(0), *catalog.candy_index("chocolate"));
}

TEST_F(WorldTest, TakingABoxInspectsItsRealContent) {
  const BoxId id = put("conveyor4/download");
  ASSERT_NE(world_.box(id), nullptr);
  auto inspection = world_.take_box(station("conveyor4/download"), "downloader");
  ASSERT_TRUE(inspection);
  EXPECT_EQ(inspection->box, id);
  EXPECT_DOUBLE_EQ(inspection->weight_g, 40.0);  // the small box's tare
  EXPECT_EQ(world_.box(id), nullptr);
  EXPECT_FALSE(world_.take_box(station("conveyor4/download"), "downloader"));
}

}  // namespace
}  // namespace sf::plant
