// The plant driven directly at its hardware faces, without any agent: our
// EtherCAT master for the smart robot, Modbus requests for the PLCs and the
// legacy robot controllers. A box is uploaded, carried to SCARA Robot 1,
// loaded by it, carried to the DENSO arm, loaded by its controller's job,
// carried to the downloader and inspected.
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "sf/plant/testing/rig.hpp"

namespace sf::plant::testing {
namespace {

std::uint16_t candy(Rig& rig, std::string_view name) {
  return line::testing::candy_number(rig.layout(), name);
}

// The whole scripted sequence (line::testing::pack_one_box), then what the
// plant saw; returns the event log as text.
std::vector<std::string> pack_one_box(Rig& rig) {
  BoxId id = 0;
  {
    RigArm arm(rig, "scara-robot-1");
    auto packed = line::testing::pack_one_box(rig, *arm);
    EXPECT_TRUE(packed) << packed.error().describe();
    id = packed ? *packed : 0;
  }
  EXPECT_EQ(id, 1U);
  EXPECT_EQ(rig.ir("downloader", transfer_plc::kBoxId), id);
  EXPECT_EQ(rig.ir("downloader", transfer_plc::kWeight), 575);  // (40 + 2.5 + 15) g in 0.1 g
  EXPECT_EQ(rig.ir("downloader", transfer_plc::kCandyTotal), 2);
  EXPECT_EQ(rig.ir("downloader", transfer_plc::kCandyCount + candy(rig, "gummy") - 1), 1);
  EXPECT_EQ(rig.ir("downloader", transfer_plc::kCandyCount + candy(rig, "lollipop") - 1), 1);
  const auto snapshot = rig.plant().snapshot();
  EXPECT_TRUE(snapshot.boxes.empty());
  EXPECT_EQ(snapshot.counters.uploaded, 1U);
  EXPECT_EQ(snapshot.counters.downloaded, 1U);
  EXPECT_EQ(snapshot.counters.placed, 2U);
  EXPECT_EQ(snapshot.counters.dropped, 0U);
  std::vector<std::string> log;
  for (const auto& e : rig.world().events().entries()) {
    log.push_back(format(e));
  }
  return log;
}

bool logged(const std::vector<std::string>& log, std::string_view needle) {
  return std::any_of(log.begin(), log.end(),
                     [&](const auto& line) { return line.find(needle) != std::string::npos; });
}

TEST(PlantScenario, ABoxIsLoadedByTheSmartRobotAndALegacyRobotAndInspected) {
  Rig rig;
  const auto log = pack_one_box(rig);
  EXPECT_TRUE(logged(log, "candy_placed scara-robot-1 box=1 slot=3 candy=gummy"))
      << ::testing::PrintToString(log);
  if (std::getenv("SF_PRINT_LOG") != nullptr) {
    for (const auto& line : log) {
      std::printf("%s\n", line.c_str());
    }
  }
  EXPECT_TRUE(logged(log, "candy_placed denso box=1 slot=7 candy=lollipop"));
  EXPECT_TRUE(logged(log, "box_inspected downloader box=1 (weight=57.5g gummy=1 lollipop=1)"));
  // The order of what happened to the box.
  std::vector<std::string> story;
  for (const auto& line : log) {
    for (const char* step :
         {"box_uploaded", "candy_placed scara", "box_entered_station conveyor4/denso", "candy_placed denso",
          "box_entered_station conveyor4/download", "box_inspected"}) {
      if (line.find(step) != std::string::npos) {
        story.emplace_back(step);
      }
    }
  }
  EXPECT_EQ(story, (std::vector<std::string>{"box_uploaded", "candy_placed scara",
                                             "box_entered_station conveyor4/denso", "candy_placed denso",
                                             "box_entered_station conveyor4/download", "box_inspected"}));
}

TEST(PlantScenario, TheSameScenarioAndSeedGiveTheSameEventLog) {
  Rig first(7);
  Rig second(7);
  const auto a = pack_one_box(first);
  const auto b = pack_one_box(second);
  EXPECT_GT(a.size(), 20U);
  EXPECT_EQ(a, b);
  // Another seed changes the machines' cycle times, and so the log's times.
  Rig other(8);
  EXPECT_NE(pack_one_box(other), a);
}

TEST(PlantScenario, TheToshibaLoadsThroughItsJobHandshake) {
  Rig rig;
  rig.hr("uploader", transfer_plc::kBoxType, 2);  // a large box
  ASSERT_EQ(rig.run_job("uploader"), FaultCode::none);
  rig.convey({"conveyor1", "conveyor3"}, 0);
  rig.hr("toshiba", robot_controller::kCandyType, candy(rig, "toffee"));
  rig.hr("toshiba", robot_controller::kSlot, 29);
  EXPECT_EQ(rig.ir("toshiba", robot_controller::kTemperature), 250);  // 25.0 °C: drives at rest
  rig.coil("toshiba", robot_controller::kStart, true);
  // While the job runs the controller reports busy, then a part in the gripper.
  EXPECT_TRUE(rig.run_until([&] { return rig.di("toshiba", robot_controller::kBusy); }, 100ms));
  EXPECT_TRUE(rig.run_until([&] { return rig.di("toshiba", robot_controller::kPartPresent); }, 5s));
  EXPECT_TRUE(rig.run_until([&] { return rig.di("toshiba", robot_controller::kDone); }, 10s));
  rig.coil("toshiba", robot_controller::kStart, false);
  rig.step();
  EXPECT_TRUE(rig.di("toshiba", robot_controller::kReady));
  EXPECT_EQ(rig.plant().snapshot().boxes.at(0).slots.at(29), "toffee");
  EXPECT_GT(rig.ir("toshiba", robot_controller::kTemperature), 250);  // warmed by the moves
  // The joints it reports put the tool where it says it is.
  const auto& spec = *rig.world().layout().robot("toshiba");
  motion::ScaraJoints q{};
  for (unsigned j = 0; j < 4; ++j) {
    q[j] = static_cast<std::int16_t>(
               rig.ir("toshiba", static_cast<std::uint16_t>(robot_controller::kJoint + j))) /
           1000.0;
  }
  const auto tool = motion::scara_forward(spec.scara, q);
  EXPECT_NEAR(tool.position.x * 1000.0,
              static_cast<std::int16_t>(rig.ir("toshiba", robot_controller::kToolX)), 2.0);
  EXPECT_NEAR(tool.position.y * 1000.0,
              static_cast<std::int16_t>(rig.ir("toshiba", robot_controller::kToolY)), 2.0);
}

TEST(PlantScenario, AJobWithoutABoxOrWithAnUnknownCandyFaultsUntilReset) {
  Rig rig;
  rig.hr("toshiba", robot_controller::kCandyType, candy(rig, "toffee"));
  EXPECT_EQ(rig.run_job("toshiba"), FaultCode::no_box);
  EXPECT_TRUE(rig.di("toshiba", robot_controller::kFault));
  // A start while faulted is ignored; fault_reset clears it.
  rig.coil("toshiba", robot_controller::kStart, true);
  rig.run_for(5ms);
  EXPECT_FALSE(rig.di("toshiba", robot_controller::kBusy));
  rig.coil("toshiba", robot_controller::kStart, false);
  rig.pulse("toshiba", robot_controller::kFaultReset);
  EXPECT_TRUE(rig.di("toshiba", robot_controller::kReady));
  rig.hr("toshiba", robot_controller::kCandyType, 99);
  EXPECT_EQ(rig.run_job("toshiba"), FaultCode::bad_job);
  rig.hr("uploader", transfer_plc::kBoxType, 9);
  EXPECT_EQ(rig.run_job("uploader"), FaultCode::bad_job);
}

}  // namespace
}  // namespace sf::plant::testing
