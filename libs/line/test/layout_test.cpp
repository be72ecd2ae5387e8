#include "sf/line/layout.hpp"

#include <algorithm>
#include <string>

#include <fmt/format.h>

#include <gtest/gtest.h>

#include "sf/motion/testing/scara_cell.hpp"

namespace sf::line {
namespace {

std::string replace(std::string text, const std::string& from, const std::string& to) {
  const auto at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  if (at != std::string::npos) {
    text.replace(at, from.size(), to);
  }
  return text;
}

// 1-based line of the first occurrence of `needle`.
int line_of(const std::string& text, const std::string& needle) {
  const auto at = text.find(needle);
  return 1 + static_cast<int>(std::count(text.begin(), text.begin() + static_cast<std::ptrdiff_t>(at), '\n'));
}

std::string refused(const std::string& yaml) {
  auto layout = parse_layout(yaml, "line.yaml");
  EXPECT_FALSE(layout) << "accepted";
  return layout ? std::string{} : layout.error().message;
}

const std::string kDefault{default_layout_yaml()};

TEST(LayoutTest, TheDefaultIsThePapersPrototype) {
  auto layout = default_layout();
  ASSERT_TRUE(layout) << layout.error().describe();
  EXPECT_EQ(layout->belts.size(), 5U);  // five Siemens-PLC conveyors
  int smart = 0;
  int legacy = 0;
  for (const auto& r : layout->robots) {
    (r.legacy() ? legacy : smart)++;
  }
  EXPECT_EQ(smart, 1);   // SCARA Robot 1 with the smart controller
  EXPECT_EQ(legacy, 2);  // DENSO VS-6577G and TOSHIBA THL300
  EXPECT_EQ(layout->uploader.plc.vendor, "Mitsubishi");
  EXPECT_EQ(layout->downloader.plc.vendor, "Mitsubishi");
  // An alternative path: conveyor1's exit is a diverter.
  EXPECT_EQ(layout->belt("conveyor1")->next.size(), 2U);
  EXPECT_DOUBLE_EQ(layout->belt("conveyor3")->length(), 1.2 + 3.0 + 1.2);
  auto station = find_station(*layout, "conveyor3/toshiba");
  ASSERT_TRUE(station);
  const auto p = layout->belts[station->belt].point_at(2.7);
  EXPECT_NEAR(p.x, 3.5, 1e-12);
  EXPECT_NEAR(p.y, 1.2, 1e-12);
}

TEST(LayoutTest, AnUnknownKeyIsNamedWithItsPlace) {
  const std::string yaml =
      replace(kDefault, "    speed_mps: 0.5\n", "    speed_mps: 0.5\n    sped_mps: 0.5\n");
  const std::string error = refused(yaml);
  EXPECT_NE(error.find(fmt::format("line.yaml:{}:", line_of(yaml, "sped_mps"))), std::string::npos) << error;
  EXPECT_NE(error.find("belts[0].sped_mps"), std::string::npos) << error;
  EXPECT_NE(error.find("unknown setting 'sped_mps'"), std::string::npos) << error;
}

TEST(LayoutTest, DuplicateNamesAreRefused) {
  const std::string yaml = replace(kDefault, "name: conveyor2\n", "name: conveyor1\n");
  const std::string error = refused(yaml);
  EXPECT_NE(error.find("duplicate belt name 'conveyor1'"), std::string::npos) << error;
  EXPECT_NE(
      error.find(fmt::format("line.yaml:{}:", line_of(yaml, "  - name: conveyor1\n    label: conveyor 2"))),
      std::string::npos)
      << error;
}

TEST(LayoutTest, BeltsThatDoNotMeetAreRefused) {
  const std::string error =
      refused(replace(kDefault, "path: [[2.0, 0.0], [5.0, 0.0]]", "path: [[2.0, 0.3], [5.0, 0.3]]"));
  EXPECT_NE(error.find("do not connect"), std::string::npos) << error;
  EXPECT_NE(error.find("line.yaml:"), std::string::npos) << error;
}

TEST(LayoutTest, AStationOutOfTheRobotsReachIsRefused) {
  const std::string error = refused(replace(kDefault, "base: [3.5, 0.35, 0.8]", "base: [3.5, 0.9, 0.8]"));
  EXPECT_NE(error.find("station conveyor2/scara1 is out of the robot's reach"), std::string::npos) << error;
  EXPECT_NE(error.find("robots[0]"), std::string::npos) << error;
}

TEST(LayoutTest, ADispenserOutOfReachIsRefused) {
  const std::string error = refused(replace(kDefault, "at: [3.3, 0.7, 0.9]", "at: [3.3, 1.7, 0.9]"));
  EXPECT_NE(error.find("dispenser 'scara1-chocolate'"), std::string::npos) << error;
}

TEST(LayoutTest, AHomeOutOfReachIsRefused) {
  const std::string error = refused(replace(kDefault, "home: [3.9, 0.35, 0.95]", "home: [5.9, 0.35, 0.95]"));
  EXPECT_NE(error.find("home (5.900, 0.350, 0.950) is out of the robot's reach"), std::string::npos) << error;
}

TEST(LayoutTest, OutOfRangeValuesAreRefused) {
  EXPECT_NE(refused(replace(kDefault, "speed_mps: 0.5\n    max_speed_mps: 0.8",
                            "speed_mps: 0.9\n    max_speed_mps: 0.8"))
                .find("speed_mps"),
            std::string::npos);
  EXPECT_NE(refused(replace(kDefault, "stock: 400, capacity: 400}", "stock: 500, capacity: 400}"))
                .find("stock 500"),
            std::string::npos);
  EXPECT_NE(refused(replace(kDefault, "{name: upload, at_m: 0.3}", "{name: upload, at_m: 2.5}"))
                .find("does not hold"),
            std::string::npos);
  EXPECT_NE(
      refused(replace(kDefault, "rows: 3, columns: 4", "rows: 3, columns: 40")).find("rows and columns"),
      std::string::npos);
  EXPECT_NE(refused(replace(kDefault, "unit_weight_g: 12.5", "unit_weight_g: -1")).find("unit_weight_g"),
            std::string::npos);
  EXPECT_NE(refused(replace(kDefault, "stock: 400", "stock: many")).find("expected an integer, found 'many'"),
            std::string::npos);
}

TEST(LayoutTest, ReferencesMustResolve) {
  EXPECT_NE(refused(replace(kDefault, "candy: toffee", "candy: liquorice"))
                .find("'liquorice' is not in the catalog"),
            std::string::npos);
  EXPECT_NE(
      refused(replace(kDefault, "next: [conveyor4]", "next: [conveyor9]")).find("'conveyor9' does not exist"),
      std::string::npos);
  EXPECT_NE(refused(replace(kDefault, "station: conveyor4/download", "station: conveyor4/nowhere"))
                .find("has no station 'nowhere'"),
            std::string::npos);
  EXPECT_NE(
      refused(replace(kDefault, "kind: legacy-scara", "kind: delta")).find("unknown robot kind 'delta'"),
      std::string::npos);
}

TEST(LayoutTest, EveryStationIsServedAndTheDownloaderReachable) {
  EXPECT_NE(refused(replace(kDefault, "    next: [conveyor1]\n",
                            "    next: [conveyor1]\n    stations:\n      - {name: spare, at_m: 5.0}\n"))
                .find("station conveyor5/spare is served by no robot"),
            std::string::npos);
  // conveyor1 feeds nothing: boxes from the uploader never reach the downloader.
  EXPECT_NE(
      refused(replace(kDefault, "next: [conveyor2, conveyor3]", "next: []")).find("no belt route leads"),
      std::string::npos);
}

TEST(LayoutTest, SyntaxErrorsNameTheirPlace) {
  const std::string error = refused("line: x\nbelts: [\n");
  EXPECT_NE(error.find("line.yaml:"), std::string::npos) << error;
  EXPECT_FALSE(load_layout("/nonexistent/layout.yaml"));
}

TEST(LayoutTest, SlotsAreCentredOnTheBox) {
  auto layout = default_layout();
  const BoxType& small = *layout->catalog.box("small-box");
  EXPECT_EQ(small.capacity(), 12);
  EXPECT_NEAR(small.slot_offset(0).x, -1.5 * 0.035, 1e-12);
  EXPECT_NEAR(small.slot_offset(0).y, -0.035, 1e-12);
  EXPECT_NEAR(small.slot_offset(11).x, 1.5 * 0.035, 1e-12);
  EXPECT_NEAR(small.slot_offset(11).y, 0.035, 1e-12);
}

}  // namespace
}  // namespace sf::line

namespace sf::line {
namespace {

// The motion tests and bench_motion work in SCARA Robot 1's cell as
// sf/motion/testing/scara_cell.hpp writes it down; it is the default layout's.
TEST(LayoutTest, TheMotionTestsCellIsTheDefaultLayouts) {
  namespace cell = motion::testing;
  auto layout = default_layout();
  ASSERT_TRUE(layout);
  const RobotSpec* robot = layout->robot("scara-robot-1");
  ASSERT_NE(robot, nullptr);
  const motion::ScaraGeometry g = cell::robot1();
  EXPECT_EQ(robot->scara.base, g.base);
  EXPECT_EQ(robot->scara.l1, g.l1);
  EXPECT_EQ(robot->scara.l2, g.l2);
  EXPECT_EQ(robot->scara.limits[2].max, g.limits[2].max);
  EXPECT_EQ(layout->dispenser("scara1-gummy")->at, cell::kGummy);
  EXPECT_EQ(layout->dispenser("scara1-chocolate")->at, cell::kChocolate);
  auto station = find_station(*layout, robot->stations.front());
  ASSERT_TRUE(station);
  const BoxType& small = *layout->catalog.box("small-box");
  EXPECT_LT(motion::norm(slot_point(*layout, *station, small, 3) - cell::kSlot3), 1e-12);
  EXPECT_LT(motion::norm(slot_point(*layout, *station, small, 8) - cell::kSlot8), 1e-12);
  EXPECT_TRUE(robot->reaches(cell::kHome));
}

}  // namespace
}  // namespace sf::line
