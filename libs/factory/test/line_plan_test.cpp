// The line's processes for the default layout and the configurations generated for them, read
// back with the controllers' own configuration parsers.
#include <algorithm>
#include <fstream>
#include <set>
#include <sstream>

#include <gtest/gtest.h>

#include "line_rig.hpp"
#include "sf/factory/line_supervisor.hpp"
#include "sf/factory/machine_config.hpp"
#include "sf/factory/order_service.hpp"
#include "sf/testing/temp_dir.hpp"

namespace sf::factory {
namespace {

namespace fs = std::filesystem;

using line_rig::endpoints_line;
using line_rig::find;
using line_rig::kLayout;
using line_rig::options;

TEST(LinePlan, EveryMachineOfTheDefaultLayoutHasItsProcessInStartOrder) {
  sf::testing::TempDir dir;
  auto plan = plan_line(options(dir.path()));
  ASSERT_TRUE(plan) << plan.error().describe();
  std::vector<std::string> names;
  for (const auto& p : plan->processes) {
    names.push_back(p.name);
  }
  const std::vector<std::string> expected{"plant",      "scara-robot-1", "conveyor1", "conveyor2",
                                          "conveyor3",  "conveyor4",     "conveyor5", "uploader",
                                          "downloader", "toshiba",       "denso",     "orders"};
  EXPECT_EQ(names, expected);
  EXPECT_EQ(find(*plan, "plant")->role, LineRole::plant);
  EXPECT_EQ(find(*plan, "scara-robot-1")->role, LineRole::machine);
  EXPECT_EQ(find(*plan, "conveyor3")->kind, GatewayKind::conveyor);
  EXPECT_EQ(find(*plan, "uploader")->kind, GatewayKind::uploader);
  EXPECT_EQ(find(*plan, "downloader")->kind, GatewayKind::downloader);
  EXPECT_EQ(find(*plan, "toshiba")->kind, GatewayKind::legacy_robot);
  EXPECT_EQ(find(*plan, "denso")->kind, GatewayKind::legacy_robot);
  EXPECT_EQ(find(*plan, "orders")->role, LineRole::orders);
}

TEST(LinePlan, OpcUaPortsCountUpFromTheBaseAndAreDistinct) {
  sf::testing::TempDir dir;
  auto plan = plan_line(options(dir.path()));
  ASSERT_TRUE(plan) << plan.error().describe();
  std::set<std::uint16_t> ports;
  std::uint16_t expected = 14850;
  for (const auto& p : plan->processes) {
    if (p.role == LineRole::plant) {
      EXPECT_EQ(p.opcua_port, 0);
      continue;
    }
    EXPECT_EQ(p.opcua_port, expected++) << p.name;
    ports.insert(p.opcua_port);
  }
  EXPECT_EQ(ports.size(), plan->processes.size() - 1);
  EXPECT_EQ(find(*plan, "orders")->opcua_port, 14850 + 10);  // after the 10 controllers
}

TEST(LinePlan, TheGeneratedConfigurationsParseWithTheControllersOwnParsers) {
  sf::testing::TempDir dir;
  auto plan = plan_line(options(dir.path()));
  ASSERT_TRUE(plan) << plan.error().describe();
  const auto endpoints = parse_plant_endpoints(endpoints_line(plan->layout, 21502, 31980));
  ASSERT_TRUE(endpoints) << endpoints.error().describe();
  ASSERT_TRUE(write_controller_configs(*plan, *endpoints));

  std::set<std::uint16_t> modbus_ports;
  for (const auto& p : plan->processes) {
    if (p.role == LineRole::machine) {
      EXPECT_EQ(p.config, dir.path() / "config" / (p.name + ".yaml"));
      auto setup = load_machine_config(p.config);
      ASSERT_TRUE(setup) << p.name << ": " << setup.error().describe();
      const auto& c = setup->config;
      EXPECT_EQ(c.controller.machine, p.name);
      EXPECT_EQ(c.ethercat.link, "udp:127.0.0.1:31980");
      EXPECT_EQ(c.controller.opcua_port, p.opcua_port);
      EXPECT_EQ(c.controller.dds.partition, "line-test");
      EXPECT_EQ(c.controller.dds.interface, "lo");
      EXPECT_TRUE(c.controller.auto_start);
    } else if (p.role == LineRole::gateway) {
      auto setup = load_gateway_config(p.config);
      ASSERT_TRUE(setup) << p.name << ": " << setup.error().describe();
      const auto& c = setup->config;
      EXPECT_EQ(c.controller.machine, p.name);
      EXPECT_EQ(c.kind, p.kind);
      EXPECT_EQ(c.modbus.host, "127.0.0.1");
      modbus_ports.insert(c.modbus.port);
      EXPECT_EQ(c.controller.opcua_port, p.opcua_port);
      EXPECT_EQ(c.controller.dds.partition, "line-test");
      EXPECT_TRUE(c.controller.auto_start);
    }
  }
  // The order service: its OPC UA port after the controllers', the run's partition.
  const LineProcess* orders = find(*plan, "orders");
  auto service = load_order_service_config(orders->config);
  ASSERT_TRUE(service) << service.error().describe();
  EXPECT_EQ(service->config.service.opcua_port, orders->opcua_port);
  EXPECT_EQ(service->config.service.dds.partition, "line-test");
  EXPECT_TRUE(service->orders.empty());
  EXPECT_EQ(orders->argv,
            (std::vector<std::string>{"/bin/sh", "orders", "--config", orders->config.string(), "--json"}));

  // Each gateway talks to its own PLC: 5 belts, uploader, downloader, 2 legacy robots.
  EXPECT_EQ(modbus_ports.size(), 9U);
  EXPECT_EQ(*modbus_ports.begin(), 21502);
}

TEST(LinePlan, WithoutALayoutFileTheConfigurationsUseTheBuiltInLayout) {
  sf::testing::TempDir dir;
  auto o = options(dir.path());
  o.layout_file.clear();
  auto plan = plan_line(o);
  ASSERT_TRUE(plan) << plan.error().describe();
  for (const auto& p : plan->processes) {
    EXPECT_EQ(std::find(p.argv.begin(), p.argv.end(), "--layout"), p.argv.end()) << p.name;
  }
  const auto endpoints = parse_plant_endpoints(endpoints_line(plan->layout, 21502, 31980));
  ASSERT_TRUE(endpoints);
  auto yaml = controller_config_yaml(*plan, *find(*plan, "toshiba"), *endpoints);
  ASSERT_TRUE(yaml) << yaml.error().describe();
  EXPECT_EQ(yaml->find("layout:"), std::string::npos) << *yaml;
  auto setup = parse_gateway_config(*yaml, "toshiba.yaml");
  ASSERT_TRUE(setup) << setup.error().describe();
  EXPECT_EQ(setup->config.kind, GatewayKind::legacy_robot);
}

TEST(LinePlan, ThePlantsReadyLineWritesTheControllersConfigurations) {
  sf::testing::TempDir dir;
  auto plan = plan_line(options(dir.path()));
  ASSERT_TRUE(plan) << plan.error().describe();
  auto processes = supervised_processes(*plan);
  ASSERT_EQ(processes.front().name, "plant");
  const auto& plant = processes.front();
  EXPECT_FALSE(plant.ready("plant: t=1.0 s"));
  EXPECT_FALSE(plant.ready(R"({"event":"ready"})"));
  const std::string line = endpoints_line(plan->layout, 21502, 31980);
  ASSERT_TRUE(plant.ready(line));
  EXPECT_FALSE(fs::exists(find(*plan, "conveyor1")->config));
  ASSERT_TRUE(plant.on_ready(line));
  EXPECT_TRUE(fs::exists(find(*plan, "conveyor1")->config));
  EXPECT_TRUE(fs::exists(find(*plan, "scara-robot-1")->config));

  // A plant without the face a controller needs is an error naming the machine.
  const std::string partial =
      R"({"endpoints":[{"machine":"conveyor1","protocol":"modbus-tcp","address":"127.0.0.1:1"}]})";
  auto st = plant.on_ready(partial);
  ASSERT_FALSE(st);
  EXPECT_NE(st.error().message.find("scara-robot-1"), std::string::npos) << st.error().message;

  // The controllers' ready lines carry their OPC UA endpoint.
  auto info = processes[1].ready(
      R"({"event":"ready","machine":"scara-robot-1","opcua":"opc.tcp://127.0.0.1:14850"})");
  ASSERT_TRUE(info);
  EXPECT_EQ(info->opcua, "opc.tcp://127.0.0.1:14850");
  EXPECT_FALSE(processes[1].ready(R"({"event":"status","machine":"scara-robot-1"})"));
  EXPECT_FALSE(processes[1].ready("{not json"));
}

TEST(LinePlan, TheOrderServiceTakesTheOrdersFile) {
  sf::testing::TempDir dir;
  const fs::path file = dir.path() / "orders.yaml";
  std::ofstream(file) << "orders:\n  - {id: o1, box: small-box, candy: {gummy: 4, toffee: 2}}\n";
  auto o = options(dir.path());
  o.orders_file = file;
  auto plan = plan_line(o);
  ASSERT_TRUE(plan) << plan.error().describe();
  ASSERT_TRUE(
      write_controller_configs(*plan, *parse_plant_endpoints(endpoints_line(plan->layout, 21502, 31980))));
  auto service = load_order_service_config(find(*plan, "orders")->config);
  ASSERT_TRUE(service) << service.error().describe();
  ASSERT_EQ(service->orders.size(), 1U);
  EXPECT_EQ(service->orders[0].id, "o1");
  o.orders_file = dir.path() / "missing-orders.yaml";
  auto refused = plan_line(o);
  ASSERT_FALSE(refused);
  EXPECT_NE(refused.error().message.find("missing-orders.yaml"), std::string::npos);
}

TEST(LinePlan, OptionalProcessesAndFreePorts) {
  sf::testing::TempDir dir;
  auto o = options(dir.path());
  o.order_service = false;
  o.cloud_config = kLayout;  // any file: the cloud reads it, the plan only passes it on
  o.opcua_base_port = 0;
  o.modbus_base_port = 0;
  o.ecat_base_port = 0;
  o.partition.clear();
  auto plan = plan_line(o);
  ASSERT_TRUE(plan) << plan.error().describe();
  EXPECT_EQ(find(*plan, "orders"), nullptr);
  ASSERT_NE(find(*plan, "cloud"), nullptr);
  EXPECT_EQ(plan->processes.back().name, "cloud");
  EXPECT_NE(plan->options.opcua_base_port, 0);
  EXPECT_NE(plan->options.modbus_base_port, 0);
  EXPECT_NE(plan->options.ecat_base_port, 0);
  EXPECT_FALSE(plan->options.partition.empty());

  // Two runs get partitions of their own.
  auto other = plan_line(o);
  ASSERT_TRUE(other);
  EXPECT_NE(other->options.partition, plan->options.partition);
}

TEST(LinePlan, TheCloudServesTheDashboardOverTlsWhenGivenTheFiles) {
  sf::testing::TempDir dir;
  auto o = options(dir.path());
  o.cloud_config = kLayout;
  o.http_port = 0;
  o.tls_cert = "chain.pem";
  o.tls_key = "key.pem";
  auto plan = plan_line(o);
  ASSERT_TRUE(plan) << plan.error().describe();
  const auto& argv = find(*plan, "cloud")->argv;
  const auto after = [&](const std::string& option) {
    auto it = std::find(argv.begin(), argv.end(), option);
    return it != argv.end() && it + 1 != argv.end() ? *(it + 1) : std::string();
  };
  EXPECT_EQ(after("--tls-cert"), std::filesystem::absolute("chain.pem").string());
  EXPECT_EQ(after("--tls-key"), std::filesystem::absolute("key.pem").string());
}

TEST(LinePlan, WithAHistorianTheRunDirectoryGetsTheCloudsConfiguration) {
  sf::testing::TempDir dir;
  auto o = options(dir.path() / "run");
  o.historian = "sqlite:" + (dir.path() / "history.db").string();
  auto plan = plan_line(o);
  ASSERT_TRUE(plan) << plan.error().describe();
  ASSERT_NE(find(*plan, "cloud"), nullptr);
  EXPECT_EQ(plan->options.cloud_config, dir.path() / "run" / "config" / "cloud.yaml");
  ASSERT_TRUE(prepare_run_dir(*plan));
  std::ifstream in(plan->options.cloud_config);
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_EQ(text, cloud_config_yaml(*plan));
  EXPECT_NE(text.find(o.historian), std::string::npos) << text;
  // The cloud reasons over the line's own layout; orders are promised within 15 minutes.
  EXPECT_NE(text.find("knowledge:"), std::string::npos) << text;
  EXPECT_NE(text.find("due_after_s: 900"), std::string::npos) << text;
  o.layout_file = dir.path() / "line.yaml";
  std::ofstream(o.layout_file) << line::default_layout_yaml();
  auto own = plan_line(o);
  ASSERT_TRUE(own) << own.error().describe();
  EXPECT_NE(cloud_config_yaml(*own).find("layout: " + o.layout_file.string()), std::string::npos)
      << cloud_config_yaml(*own);
}

TEST(LinePlan, BadOptionsAreRefusedBeforeAnythingStarts) {
  sf::testing::TempDir dir;
  auto expect_refused = [&](LineOptions o, std::string_view words) {
    auto plan = plan_line(std::move(o));
    ASSERT_FALSE(plan) << words;
    EXPECT_NE(plan.error().describe().find(words), std::string::npos) << plan.error().describe();
  };
  auto o = options(dir.path());
  o.layout_file = dir.path() / "nowhere.yaml";
  expect_refused(o, "nowhere.yaml");
  o = options(dir.path());
  o.opcua_base_port = 65530;
  expect_refused(o, "--opcua-base-port 65530");
  o = options(dir.path());
  o.partition = "a b";
  expect_refused(o, "partition 'a b'");
  o = options(dir.path());
  o.program = dir.path() / "no-such-program";
  expect_refused(o, "no smartfactory program");
  o = options(dir.path());
  o.cloud_config = dir.path() / "cloud.yaml";
  expect_refused(o, "cloud.yaml");

  const fs::path bad = dir.path() / "bad-layout.yaml";
  std::ofstream(bad) << "line: x\nbelts: 3\n";
  o = options(dir.path());
  o.layout_file = bad;
  expect_refused(o, "bad-layout.yaml");
}

TEST(LinePlan, PlantEndpointsLinesAreChecked) {
  EXPECT_FALSE(parse_plant_endpoints("endpoints"));
  EXPECT_FALSE(parse_plant_endpoints(R"({"endpoints": 3})"));
  EXPECT_FALSE(parse_plant_endpoints(R"({"endpoints": [{"machine": "c1"}]})"));
  auto e =
      parse_plant_endpoints(R"({"endpoints":[{"machine":"c1","protocol":"modbus-tcp","address":"h:1"}]})");
  ASSERT_TRUE(e);
  ASSERT_EQ(e->size(), 1U);
  EXPECT_EQ((*e)[0].address, "h:1");
}

TEST(LinePlan, ACommandIsThereWhenItsOwnHelpAnswers) {
  sf::testing::TempDir dir;
  // Like a CLI11 program: an unknown command's --help prints the program's own help, exit 0.
  const fs::path program = dir.path() / "prog";
  std::ofstream(program) << "#!/bin/sh\nif [ \"$1\" = line ]; then echo 'Usage: prog line [OPTIONS]'; "
                            "else echo 'Usage: prog [OPTIONS] [SUBCOMMAND]'; echo '  line   the line'; fi\n";
  fs::permissions(program, fs::perms::owner_all);
  EXPECT_TRUE(has_command(program, "line"));
  EXPECT_FALSE(has_command(program, "orders"));
  EXPECT_FALSE(has_command(dir.path() / "missing", "line"));
}

}  // namespace
}  // namespace sf::factory
