// The smart robot's IPC configuration: the shipped example, and every kind of
// mistake named with file:line:column and the key.
#include "sf/factory/machine_config.hpp"

#include <gtest/gtest.h>

namespace sf::factory {
namespace {

std::string refused(std::string_view yaml) {
  auto setup = parse_machine_config(yaml, "machine.yaml");
  EXPECT_FALSE(setup) << yaml;
  return setup ? std::string() : setup.error().describe();
}

TEST(MachineConfig, TheShippedExampleIsTheDefaultLinesSmartRobot) {
  auto setup = load_machine_config(SF_SOURCE_DIR "/configs/scara-robot-1.yaml");
  ASSERT_TRUE(setup) << setup.error().describe();
  const MachineConfig& c = setup->config;
  EXPECT_EQ(c.controller.machine, "scara-robot-1");
  EXPECT_TRUE(c.controller.auto_start);
  EXPECT_EQ(c.ethercat.link, "udp:127.0.0.1:34980");
  EXPECT_EQ(c.ethercat.cycle, std::chrono::microseconds(1000));
  EXPECT_EQ(c.controller.opcua_port, 4850);
  EXPECT_EQ(c.controller.dds.interface, "lo");
  ASSERT_NE(setup->layout.robot("scara-robot-1"), nullptr);
  const SmartRobotConfig robot = smart_robot_config(c);
  EXPECT_EQ(robot.robot, "scara-robot-1");
  EXPECT_DOUBLE_EQ(robot.limits.cycle, 1e-3);
  EXPECT_TRUE(robot.auto_start);
}

TEST(MachineConfig, DefaultsNeedOnlyTheMachine) {
  auto setup = parse_machine_config("machine: scara-robot-1\n");
  ASSERT_TRUE(setup) << setup.error().describe();
  EXPECT_FALSE(setup->config.controller.auto_start);
  EXPECT_EQ(setup->config.controller.dds.machining_domain, 10U);
}

TEST(MachineConfig, MistakesAreNamedWithTheirPlace) {
  std::string e = refused("machine: scara-robot-1\nethercat:\n  link: udp:127.0.0.1:34980\n  cycle: 1000\n");
  EXPECT_NE(e.find("machine.yaml:4:"), std::string::npos) << e;
  EXPECT_NE(e.find("unknown setting 'cycle'"), std::string::npos) << e;
  e = refused("machine: scara-robot-1\nethercat: {cycle_us: 50}\n");
  EXPECT_NE(e.find("125 µs .. 100 ms"), std::string::npos) << e;
  e = refused("machine: scara-robot-1\ndds: {machining_domain: 300}\n");
  EXPECT_NE(e.find("0..232"), std::string::npos) << e;
  e = refused("machine: scara-robot-1\nstart: running\n");
  EXPECT_NE(e.find("start is stopped or execute"), std::string::npos) << e;
  e = refused("machine: scara-robot-1\npick_place: {grip_timeout_ms: 0}\n");
  EXPECT_NE(e.find("grip_timeout_ms"), std::string::npos) << e;
  e = refused("machine: scara-robot-1\nlayout: nowhere.yaml\n");
  EXPECT_NE(e.find("nowhere.yaml"), std::string::npos) << e;
  e = refused("ethercat: {cycle_us: 1000}\n");
  EXPECT_NE(e.find("machine"), std::string::npos) << e;
}

TEST(MachineConfig, OnlyASmartRobotHasAMachineController) {
  std::string e = refused("machine: toshiba\n");
  EXPECT_NE(e.find("'toshiba' is a legacy robot"), std::string::npos) << e;
  EXPECT_NE(e.find("machine.yaml:1:"), std::string::npos) << e;
  e = refused("machine: scara-robot-9\n");
  EXPECT_NE(e.find("the layout has no robot 'scara-robot-9'"), std::string::npos) << e;
}

}  // namespace
}  // namespace sf::factory
