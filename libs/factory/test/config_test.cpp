// Gateway configurations: every key read, errors that name file:line:column
// and the key, configurations that do not fit their layout refused, and the
// example configurations in configs/gateways/ valid for the default layout.
#include <filesystem>
#include <set>

#include <gtest/gtest.h>

#include "sf/factory/gateway_config.hpp"

namespace sf::factory {
namespace {

using namespace std::chrono_literals;

std::string error_of(std::string_view yaml) {
  auto setup = parse_gateway_config(yaml, "gw.yaml");
  return setup ? "" : setup.error().message;
}

TEST(GatewayConfig, ReadsEveryKey) {
  auto setup = parse_gateway_config(R"(
machine: toshiba
kind: legacy-robot
serial_number: THL300-0042
start: execute
job_timeout_s: 4
modbus: {host: plc.local, port: 1510, unit_id: 1, timeout_ms: 300, poll_period_ms: 10, stale_after_ms: 800}
opcua: {port: 4842}
dds: {machining_domain: 20, conveying_domain: 21, interface: eth1, partition: line-2, lease_ms: 500}
robot: {station: conveyor3/toshiba, approach_m: 0.04, grip_s: 0.2}
)");
  ASSERT_TRUE(setup) << setup.error().describe();
  const GatewayConfig& c = setup->config;
  EXPECT_EQ(c.kind, GatewayKind::legacy_robot);
  EXPECT_TRUE(c.controller.auto_start);
  EXPECT_EQ(c.controller.job_timeout, 4s);
  EXPECT_EQ(c.modbus.host, "plc.local");
  EXPECT_EQ(c.modbus.port, 1510);
  EXPECT_EQ(c.modbus.unit_id, 1);
  EXPECT_EQ(c.modbus.timeout, 300ms);
  EXPECT_EQ(c.modbus.poll_period, 10ms);
  EXPECT_EQ(c.modbus.stale_after, 800ms);
  EXPECT_EQ(c.controller.opcua_port, 4842);
  EXPECT_EQ(c.controller.dds.machining_domain, 20U);
  EXPECT_EQ(c.controller.dds.conveying_domain, 21U);
  EXPECT_EQ(c.controller.dds.interface, "eth1");
  EXPECT_EQ(c.controller.dds.partition, "line-2");
  EXPECT_EQ(c.controller.dds.lease, 500ms);
  EXPECT_EQ(c.robot.grip, 200ms);
}

TEST(GatewayConfig, DefaultsArePaperLike) {
  auto setup = parse_gateway_config("machine: conveyor2\nkind: conveyor\n");
  ASSERT_TRUE(setup) << setup.error().describe();
  EXPECT_EQ(setup->config.modbus.poll_period, 20ms);  // the issue's default poll period
  EXPECT_FALSE(setup->config.controller.auto_start);  // an operator starts it
  EXPECT_EQ(setup->config.controller.dds.machining_domain, 10U);
  EXPECT_EQ(setup->config.controller.dds.interface, "lo");
}

TEST(GatewayConfig, ErrorsNameFileLineColumnAndKey) {
  EXPECT_EQ(error_of("machine: conveyor2\nkind: conveyor\nmodbus: {poll_period_ms: 0}\n"),
            "gw.yaml:3:26: modbus.poll_period_ms: must be a duration of 1 ms up to 11 days");
  EXPECT_EQ(error_of("machine: conveyor2\nkind: belt\n"),
            "gw.yaml:2:7: kind: unknown kind 'belt' (known: conveyor, uploader, downloader, legacy-robot)");
  EXPECT_EQ(error_of("machine: conveyor9\nkind: conveyor\n"),
            "gw.yaml:1:10: machine: the layout has no belt 'conveyor9'");
  EXPECT_EQ(error_of("machine: conveyor2\nkind: conveyor\ndds:\n  machining_domain: 300\n"),
            "gw.yaml:4:21: dds.machining_domain: a DDS domain id is 0..232");
  EXPECT_EQ(error_of("machine: conveyor2\nkind: conveyor\ndds: {lease_ms: 10}\n"),
            "gw.yaml:3:17: dds.lease_ms: a lease shorter than 50 ms would declare a busy controller dead");
}

TEST(GatewayConfig, ConfigurationsThatDoNotFitTheLayoutAreRefused) {
  const std::pair<std::string_view, std::string_view> cases[] = {
      {"machine: scara-robot-1\nkind: legacy-robot\n", "with its own controller"},
      {"machine: toshiba\nkind: conveyor\n", "the layout has no belt 'toshiba'"},
      {"machine: uploader\nkind: downloader\n", "the layout's downloader is 'downloader'"},
      {"machine: toshiba\nkind: legacy-robot\nrobot: {station: conveyor4/denso}\n",
       "not one of toshiba's stations"},
      {"machine: conveyor1\nkind: conveyor\nrobot: {grip_s: 1}\n", "belong to a legacy-robot gateway"},
      {"machine: conveyor1\nkind: conveyor\nlayout: no-such-layout.yaml\n", "no-such-layout.yaml"},
      {"machine: conveyor1\nkind: conveyor\nspeed: 3\n", "speed"},
      {"machine: conveyor1\n", "kind"},
      {"[1, 2]", "gw.yaml"},
      {"machine: conveyor1\nkind: conveyor\nstart: [execute\n", "gw.yaml"},
  };
  for (const auto& [yaml, part] : cases) {
    const std::string e = error_of(yaml);
    EXPECT_NE(e.find(part), std::string::npos) << yaml << " → " << e;
    EXPECT_EQ(e.rfind("gw.yaml", 0), 0U) << e;  // every error says where
  }
}

// Each device kind's example runs against the default layout as it is.
TEST(GatewayConfig, TheExampleConfigurationsAreValid) {
  std::set<GatewayKind> kinds;
  for (const auto& entry : std::filesystem::directory_iterator(SF_SOURCE_DIR "/configs/gateways")) {
    auto setup = load_gateway_config(entry.path());
    ASSERT_TRUE(setup) << setup.error().describe();
    EXPECT_NE(setup->config.modbus.port, 0)
        << entry.path() << ": the plant's PLCs have no ports in the layout";
    kinds.insert(setup->config.kind);
  }
  EXPECT_EQ(kinds.size(), 4U);
}

}  // namespace
}  // namespace sf::factory
