// Each fault of faults.hpp injected, observed at the hardware face (Modbus
// registers and exceptions, CiA 402 status and error code, EtherCAT working
// counter) and cleared.
#include "sf/plant/faults.hpp"

#include "sf/plant/testing/rig.hpp"

namespace sf::plant::testing {
namespace {

FaultSpec fault(std::string_view text) {
  auto f = parse_fault(text);
  EXPECT_TRUE(f) << f.error().describe();
  return f ? *f : FaultSpec{};
}

TEST(FaultSpecTest, ParsesEveryKindAndRefusesNonsense) {
  EXPECT_EQ(fault("jam:conveyor2").kind, FaultKind::jam);
  const auto axis = fault("axis-fault:scara1:2:0x5441");
  EXPECT_EQ(axis.argument, 2U);
  EXPECT_EQ(axis.code, 0x5441);
  EXPECT_EQ(fault("axis-fault:scara-robot-1:1").code, 0x7310);
  EXPECT_EQ(fault("plc-exception:uploader").argument, 4U);
  EXPECT_EQ(fault("plc-exception:uploader:6").argument, 6U);
  EXPECT_EQ(format(fault("plc-exception:uploader:6")), "plc-exception:uploader:6");
  EXPECT_FALSE(parse_fault("meltdown:scara1"));
  EXPECT_FALSE(parse_fault("jam"));
  EXPECT_FALSE(parse_fault("axis-fault:scara1"));
  EXPECT_FALSE(parse_fault("axis-fault:scara1:9"));
  EXPECT_FALSE(parse_fault("jam:conveyor1:3"));
  EXPECT_FALSE(parse_fault("box-drop:first"));
}

TEST(FaultSpecTest, AMixupNamesItsDispenserAndRoundTrips) {
  const auto mixup = fault("mixup:toshiba-toffee");
  EXPECT_EQ(mixup.kind, FaultKind::mixup);
  EXPECT_EQ(mixup.target, "toshiba-toffee");
  EXPECT_EQ(format(mixup), "mixup:toshiba-toffee");
  EXPECT_EQ(fault(format(mixup)), mixup);
  EXPECT_FALSE(parse_fault("mixup"));
  EXPECT_FALSE(parse_fault("mixup:"));
  EXPECT_FALSE(parse_fault("mixup:toshiba-toffee:chocolate"));
  auto unknown = parse_fault("mix-up:toshiba-toffee");
  ASSERT_FALSE(unknown);
  EXPECT_NE(unknown.error().message.find("mixup"), std::string::npos) << unknown.error().message;
}

TEST(PlantFaults, UnknownTargetsAreRefused) {
  Rig rig;
  EXPECT_FALSE(rig.plant().inject(fault("jam:conveyor9")));
  EXPECT_FALSE(rig.plant().inject(fault("cable-cut:denso")));  // a legacy robot has no EtherCAT
  EXPECT_FALSE(rig.plant().inject(fault("plc-unreachable:scara-robot-1")));
  EXPECT_FALSE(rig.plant().inject(fault("mixup:toshiba-mint")));
  EXPECT_FALSE(rig.plant().inject(fault("mixup:toshiba")));  // a robot is not a dispenser
  EXPECT_FALSE(rig.plant().clear(fault("mixup:conveyor2")));
  EXPECT_FALSE(rig.plant().inject(fault("overheat:scara-robot-1")));  // its slave has no temperature
  EXPECT_TRUE(rig.plant().active_faults().empty());
}

TEST(PlantFaults, AMixupIsRefusedWhenTheCatalogHasNoOtherCandy) {
  ManualClock clock;
  Layout layout = *default_layout();
  layout.catalog.candy_types.resize(1);  // chocolate only
  std::erase_if(layout.dispensers, [](const DispenserSpec& d) { return d.candy != "chocolate"; });
  for (auto& r : layout.robots) {
    std::erase_if(r.dispensers,
                  [](const std::string& d) { return d.find("chocolate") == std::string::npos; });
  }
  Plant plant(std::move(layout), clock);
  auto refused = plant.inject(fault("mixup:denso-chocolate"));
  ASSERT_FALSE(refused);
  EXPECT_NE(refused.error().message.find("no other candy type"), std::string::npos)
      << refused.error().message;
}

TEST(PlantFaults, AMixedUpDispenserGivesTheLegacyRobotTheNextCandyUntilCleared) {
  Rig rig;
  const auto& catalog = rig.world().layout().catalog;
  const auto toffee = *catalog.candy_index("toffee");
  const auto chocolate = *catalog.candy_index("chocolate");
  ASSERT_EQ((toffee + 1) % catalog.candy_types.size(), chocolate);  // the catalog's last wraps to its first
  rig.hr("uploader", transfer_plc::kBoxType, 1);
  ASSERT_EQ(rig.run_job("uploader"), FaultCode::none);
  rig.convey({"conveyor1", "conveyor3"}, 0);
  ASSERT_TRUE(rig.plant().inject(fault("mixup:toshiba-toffee")));
  EXPECT_EQ(rig.plant().snapshot().faults, std::vector<std::string>{"mixup:toshiba-toffee"});
  EXPECT_EQ(rig.world().events().entries().back().kind, EventKind::fault_raised);
  EXPECT_EQ(rig.world().events().entries().back().where, "toshiba-toffee");
  // The controller asks for toffee; its vacuum cup cannot tell, the job succeeds with chocolate.
  rig.hr("toshiba", robot_controller::kCandyType, static_cast<std::uint16_t>(toffee + 1));
  EXPECT_EQ(rig.run_job("toshiba"), FaultCode::none);
  const Event* picked = nullptr;
  for (const auto& e : rig.world().events().entries()) {
    picked = e.kind == EventKind::candy_picked ? &e : picked;
  }
  ASSERT_NE(picked, nullptr);
  EXPECT_EQ(picked->candy, "chocolate");
  EXPECT_EQ(picked->detail, "toshiba-toffee");
  EXPECT_EQ(rig.plant().snapshot().boxes.at(0).slots.at(0), "chocolate");
  const auto& dispensers = rig.world().layout().dispensers;
  EXPECT_EQ(rig.world().stock(static_cast<std::size_t>(rig.world().layout().dispenser("toshiba-toffee") -
                                                       dispensers.data())),
            399);

  ASSERT_TRUE(rig.plant().clear(fault("mixup:toshiba-toffee")));
  EXPECT_TRUE(rig.plant().active_faults().empty());
  EXPECT_EQ(rig.world().events().entries().back().kind, EventKind::fault_cleared);
  rig.run_for(3s);  // the arm is back home
  rig.hr("toshiba", robot_controller::kSlot, 1);
  EXPECT_EQ(rig.run_job("toshiba"), FaultCode::none);
  EXPECT_EQ(rig.plant().snapshot().boxes.at(0).slots.at(1), "toffee");
}

TEST(PlantFaults, AJamLatchesTheConveyorFaultUntilResetAfterItIsGone) {
  Rig rig;
  rig.coil("conveyor1", conveyor_plc::kMotorRun, true);
  rig.step();
  EXPECT_TRUE(rig.di("conveyor1", conveyor_plc::kRunning));
  ASSERT_TRUE(rig.plant().inject(fault("jam:conveyor1")));
  rig.step();
  EXPECT_TRUE(rig.di("conveyor1", conveyor_plc::kJam));
  EXPECT_TRUE(rig.di("conveyor1", conveyor_plc::kExitEye));  // photo-eye stuck
  EXPECT_TRUE(rig.di("conveyor1", conveyor_plc::kFault));
  EXPECT_FALSE(rig.di("conveyor1", conveyor_plc::kRunning));
  EXPECT_EQ(rig.ir("conveyor1", conveyor_plc::kFaultCode), static_cast<std::uint16_t>(FaultCode::jam));
  EXPECT_EQ(rig.plant().snapshot().faults, std::vector<std::string>{"jam:conveyor1"});
  ASSERT_TRUE(rig.plant().clear(fault("jam:conveyor1")));
  rig.step();
  EXPECT_FALSE(rig.di("conveyor1", conveyor_plc::kJam));
  EXPECT_TRUE(rig.di("conveyor1", conveyor_plc::kFault));  // latched
  rig.pulse("conveyor1", conveyor_plc::kFaultReset);
  EXPECT_FALSE(rig.di("conveyor1", conveyor_plc::kFault));
  EXPECT_TRUE(rig.di("conveyor1", conveyor_plc::kRunning));
  EXPECT_TRUE(rig.plant().active_faults().empty());
}

TEST(PlantFaults, AnEmptyDispenserFailsTheLegacyRobotsPick) {
  Rig rig;
  rig.hr("uploader", transfer_plc::kBoxType, 1);
  ASSERT_EQ(rig.run_job("uploader"), FaultCode::none);
  rig.convey({"conveyor1", "conveyor3"}, 0);
  ASSERT_TRUE(rig.plant().inject(fault("dispenser-empty:toshiba-toffee")));
  rig.hr("toshiba", robot_controller::kCandyType,
         static_cast<std::uint16_t>(*rig.world().layout().catalog.candy_index("toffee") + 1));
  EXPECT_EQ(rig.run_job("toshiba"), FaultCode::dispenser_empty);
  EXPECT_EQ(rig.world().counters().pick_missed, 1U);
  ASSERT_TRUE(rig.plant().clear(fault("dispenser-empty:toshiba-toffee")));
  rig.pulse("toshiba", robot_controller::kFaultReset);
  rig.run_for(3s);  // the arm is back home
  EXPECT_EQ(rig.run_job("toshiba"), FaultCode::none);
  EXPECT_EQ(rig.plant().snapshot().boxes.at(0).slots.at(0), "toffee");
}

TEST(PlantFaults, AnAxisFaultShowsInTheStatuswordAndErrorCodeAndIsReset) {
  Rig rig;
  RigArm arm(rig, "scara-robot-1");
  ASSERT_TRUE(rig.plant().inject(fault("axis-fault:scara-robot-1:1:0x5441")));
  EXPECT_TRUE(rig.run_until([&] { return arm->axis(1).fault(); }, 100ms));
  EXPECT_TRUE(arm->axis(1).statusword() & 0x0008);  // fault bit
  EXPECT_TRUE(arm->axis(0).enabled());
  auto code = arm->master().sdo_read<std::uint16_t>(0, 0x603F + 0x800, 0);
  ASSERT_TRUE(code) << code.error().describe();
  EXPECT_EQ(*code, 0x5441);
  ASSERT_TRUE(rig.plant().clear(fault("axis-fault:scara-robot-1:1")));
  arm->axis(1).fault_reset();
  arm->axis(1).enable();
  EXPECT_TRUE(rig.run_until([&] { return arm->axis(1).enabled(); }, 200ms));
}

TEST(PlantFaults, ACutCableLosesTheSlaveAndItComesBackWhenRestored) {
  Rig rig;
  RigArm arm(rig, "scara-robot-1");
  EXPECT_TRUE(arm->master().last_exchange().ok());
  ASSERT_TRUE(rig.plant().inject(fault("cable-cut:scara-robot-1")));
  rig.step();
  EXPECT_FALSE(arm->master().last_exchange().ok());
  EXPECT_EQ(arm->master().last_exchange().responding, 0);
  ASSERT_TRUE(rig.plant().clear(fault("cable-cut:scara-robot-1")));
  // The slave restarts in INIT; the master's maintenance brings it back to OP.
  EXPECT_TRUE(rig.run_until(
      [&] {
        arm->master().maintain();
        return arm->master().last_exchange().ok();
      },
      5s));
}

TEST(PlantFaults, AnUnreachablePlcTimesOutAndAnswersAgainWhenCleared) {
  Rig rig;
  ASSERT_TRUE(rig.plant().inject(fault("plc-unreachable:conveyor2")));
  auto read = rig.plc("conveyor2").read_discrete_inputs(0, 4);
  ASSERT_FALSE(read);
  EXPECT_EQ(read.error().code, Errc::timeout);
  ASSERT_TRUE(rig.plant().clear(fault("plc-unreachable:conveyor2")));
  EXPECT_TRUE(rig.plc("conveyor2").read_discrete_inputs(0, 4));
}

TEST(PlantFaults, APlcAnsweringExceptionsGivesTheTypedCode) {
  Rig rig;
  ASSERT_TRUE(rig.plant().inject(fault("plc-exception:uploader:6")));
  auto read = rig.plc("uploader").read_input_registers(0, 2);
  ASSERT_FALSE(read);
  EXPECT_EQ(read.error().code, Errc::remote);
  ASSERT_TRUE(read.error().exception.has_value());
  EXPECT_EQ(*read.error().exception, modbus::ExceptionCode::server_device_busy);
  ASSERT_TRUE(rig.plant().clear(fault("plc-exception:uploader")));
  EXPECT_TRUE(rig.plc("uploader").read_input_registers(0, 2));
}

// The legacy controller's temperature register (0.1 °C): the drives at ambient, then heating
// with their cooling lost past the robot's limit, then cooling back once it is repaired.
TEST(PlantFaults, AnOverheatingRobotReportsItsDrivesTemperatureRisingAndFalling) {
  Rig rig;
  const auto temperature = [&] { return rig.ir("denso", robot_controller::kTemperature) / 10.0; };
  rig.run_for(10ms);
  EXPECT_EQ(temperature(), kAmbientTemperatureC);
  ASSERT_TRUE(rig.plant().inject(fault("overheat:denso")));
  EXPECT_EQ(format(rig.plant().active_faults().at(0)), "overheat:denso");
  rig.run_for(std::chrono::minutes(10));
  EXPECT_GT(temperature(), robot_controller::kMaxTemperature);
  ASSERT_TRUE(rig.plant().clear(fault("overheat:denso")));
  rig.run_for(std::chrono::minutes(10));
  EXPECT_LT(temperature(), robot_controller::kMaxTemperature);
  EXPECT_GT(temperature(), kAmbientTemperatureC);
}

TEST(PlantFaults, ADroppedBoxIsLostAndCounted) {
  Rig rig;
  rig.hr("uploader", transfer_plc::kBoxType, 1);
  ASSERT_EQ(rig.run_job("uploader"), FaultCode::none);
  rig.convey({"conveyor1", "conveyor2"}, 0);
  ASSERT_TRUE(rig.plant().inject(fault("box-drop:1")));
  rig.step();
  EXPECT_FALSE(rig.di("conveyor2", conveyor_plc::kStationEye));
  EXPECT_EQ(rig.ir("conveyor2", conveyor_plc::kStationBox), 0);
  EXPECT_EQ(rig.plant().snapshot().counters.boxes_lost, 1U);
  EXPECT_EQ(rig.world().events().entries().back().kind, EventKind::box_lost);
  EXPECT_FALSE(rig.plant().clear(fault("box-drop:1")));
}

TEST(PlantFaults, ATimedFaultComesAndGoesOnSimulatedTime) {
  Rig rig;
  auto jam = fault("jam:conveyor4");
  jam.at = std::chrono::seconds{1};
  jam.duration = std::chrono::seconds{2};
  ASSERT_TRUE(rig.plant().inject(jam));
  rig.run_for(990ms);
  EXPECT_FALSE(rig.di("conveyor4", conveyor_plc::kJam));
  rig.run_for(20ms);
  EXPECT_TRUE(rig.di("conveyor4", conveyor_plc::kJam));
  rig.run_for(1980ms);
  EXPECT_TRUE(rig.di("conveyor4", conveyor_plc::kJam));
  rig.run_for(20ms);
  EXPECT_FALSE(rig.di("conveyor4", conveyor_plc::kJam));
}

}  // namespace
}  // namespace sf::plant::testing
