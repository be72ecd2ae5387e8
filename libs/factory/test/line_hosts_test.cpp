// The line on several hosts (line_hosts.hpp): each process's namespace, interfaces and addresses,
// the `ip` commands they imply, and the processes' arguments and configurations that use them.
#include <unistd.h>

#include <algorithm>
#include <map>
#include <set>

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include "line_rig.hpp"
#include "sf/core/process.hpp"
#include "sf/factory/line_hosts.hpp"
#include "sf/factory/line_supervisor.hpp"
#include "sf/factory/machine_config.hpp"
#include "sf/factory/order_service.hpp"
#include "sf/testing/temp_dir.hpp"

namespace sf::factory {
namespace {

namespace fs = std::filesystem;
using line_rig::find;
using K = HostNetworkKind;
using namespace std::chrono_literals;

// The default layout with the cloud and the order service, each process in its namespace.
Result<LinePlan> hosts_plan(const fs::path& run_dir) {
  auto o = line_rig::options(run_dir);
  o.historian = fmt::format("sqlite:{}/history.db", run_dir.string());
  o.hosts = true;
  return plan_line(o);
}

std::vector<K> kinds(const ProcessHost& h) {
  std::vector<K> out;
  for (const auto& i : h.interfaces) {
    out.push_back(i.network);
  }
  return out;
}

bool contains(const std::vector<std::string>& argv, const std::vector<std::string>& part) {
  return std::search(argv.begin(), argv.end(), part.begin(), part.end()) != argv.end();
}

TEST(HostPlan, EveryProcessHasANamespaceWithAnInterfacePerProtocolOfItsRole) {
  sf::testing::TempDir dir;
  auto plan = hosts_plan(dir.path());
  ASSERT_TRUE(plan) << plan.error().describe();
  ASSERT_TRUE(plan->hosts);
  const auto& h = *plan->hosts;
  EXPECT_EQ(h.prefix, hosts_prefix(dir.path()));
  EXPECT_EQ(h.line_netns, h.prefix + "-net");
  ASSERT_EQ(h.hosts.size(), plan->processes.size());
  for (std::size_t i = 0; i < h.hosts.size(); ++i) {
    EXPECT_EQ(h.hosts[i].process, plan->processes[i].name);
    EXPECT_EQ(h.hosts[i].netns, h.prefix + "-" + plan->processes[i].name);
  }

  // The plant: the field network, and one end of every smart robot's EtherCAT cable.
  const auto* plant = h.host("plant");
  EXPECT_EQ(kinds(*plant), (std::vector<K>{K::field, K::ethercat}));
  EXPECT_EQ(plant->address(K::field), "10.77.1.1");
  EXPECT_EQ(plant->address(K::ethercat), "");
  // The smart robot's IPC: EtherCAT to the plant, DDS to the other agents, OPC UA to the cloud.
  const auto* robot = h.host("scara-robot-1");
  EXPECT_EQ(kinds(*robot), (std::vector<K>{K::ethercat, K::dds, K::opcua}));
  const auto* cable = robot->on(K::ethercat);
  EXPECT_EQ(cable->name, "ecat0");
  EXPECT_EQ(cable->peer_netns, plant->netns);
  EXPECT_EQ(cable->peer, plant->on(K::ethercat)->name);
  EXPECT_EQ(plant->on(K::ethercat)->peer_netns, robot->netns);
  EXPECT_EQ(robot->address(K::dds), "10.77.2.2");
  EXPECT_EQ(robot->address(K::opcua), "10.77.3.2");
  // A gateway (the paper's Raspberry Pi): Modbus to its PLC instead of EtherCAT.
  EXPECT_EQ(kinds(*h.host("conveyor1")), (std::vector<K>{K::field, K::dds, K::opcua}));
  EXPECT_EQ(kinds(*h.host("toshiba")), (std::vector<K>{K::field, K::dds, K::opcua}));
  EXPECT_EQ(h.host("conveyor1")->on(K::dds)->name, "dds0");
  EXPECT_EQ(h.host("conveyor1")->on(K::dds)->peer_netns, h.line_netns);
  // The order service negotiates and reports; the cloud only reads OPC UA.
  EXPECT_EQ(kinds(*h.host("orders")), (std::vector<K>{K::dds, K::opcua}));
  EXPECT_EQ(kinds(*h.host("cloud")), (std::vector<K>{K::opcua}));
}

TEST(HostPlan, AddressesAreDistinctAndInTheirNetworksSubnet) {
  sf::testing::TempDir dir;
  auto plan = hosts_plan(dir.path());
  ASSERT_TRUE(plan) << plan.error().describe();
  std::map<K, std::string> subnet;
  for (const auto& n : plan->hosts->networks) {
    subnet[n.kind] = n.cidr();
    EXPECT_EQ(n.bridge, fmt::format("br-{}", to_string(n.kind)));
  }
  EXPECT_EQ(subnet, (std::map<K, std::string>{
                        {K::field, "10.77.1.0/24"}, {K::dds, "10.77.2.0/24"}, {K::opcua, "10.77.3.0/24"}}));
  std::set<std::string> addresses;
  std::set<std::string> bridge_ports;
  std::size_t members = 0;
  for (const auto& host : plan->hosts->hosts) {
    for (const auto& i : host.interfaces) {
      if (i.network == K::ethercat) {
        continue;
      }
      ++members;
      addresses.insert(i.address);
      bridge_ports.insert(i.peer);
      EXPECT_TRUE(i.address.starts_with(subnet[i.network].substr(0, 8))) << host.process << ": " << i.address;
      EXPECT_LE(i.peer.size(), 15U) << i.peer;  // IFNAMSIZ
    }
  }
  EXPECT_EQ(addresses.size(), members);
  EXPECT_EQ(bridge_ports.size(), members);
}

TEST(HostPlan, TheCommandsMakeEveryNamespaceBridgeAndCableOnceAndRemoveThem) {
  sf::testing::TempDir dir;
  auto plan = hosts_plan(dir.path());
  ASSERT_TRUE(plan) << plan.error().describe();
  const auto& h = *plan->hosts;
  const auto setup = host_setup_commands(h);
  std::multiset<std::string> added_namespaces;
  std::multiset<std::string> bridges;
  std::multiset<std::string> veths;  // "<namespace>/<name>"
  std::multiset<std::string> addresses;
  for (const auto& c : setup) {
    ASSERT_EQ(c.front(), "ip") << fmt::format("{}", fmt::join(c, " "));
    if (contains(c, {"netns", "add"})) {
      added_namespaces.insert(c.back());
    } else if (contains(c, {"type", "bridge"})) {
      EXPECT_EQ(c[2], h.line_netns);
      bridges.insert(c[5]);
    } else if (contains(c, {"type", "veth"})) {
      veths.insert(c[2] + "/" + c[5]);
      veths.insert(c.back() + "/" + c[10]);
    } else if (contains(c, {"addr", "add"})) {
      addresses.insert(c[2] + "/" + c[5]);
      // Only addresses of the line's own networks, never anything routed elsewhere.
      EXPECT_TRUE(c[5].starts_with("10.77.") && c[5].ends_with("/24")) << c[5];
    }
  }
  const auto all = h.namespaces();
  EXPECT_EQ(added_namespaces, std::multiset<std::string>(all.begin(), all.end()));
  EXPECT_EQ(bridges, (std::multiset<std::string>{"br-dds", "br-field", "br-opcua"}));
  std::multiset<std::string> expected_veths;
  std::multiset<std::string> expected_addresses;
  for (const auto& host : h.hosts) {
    for (const auto& i : host.interfaces) {
      expected_veths.insert(host.netns + "/" + i.name);
      if (i.network != K::ethercat) {
        expected_veths.insert(i.peer_netns + "/" + i.peer);
        expected_addresses.insert(host.netns + "/" + i.address + "/24");
      }
    }
  }
  EXPECT_EQ(veths, expected_veths);  // the plant's EtherCAT ends once, made from the robots' side
  EXPECT_EQ(addresses, expected_addresses);
  // Every bridge port joins its network's bridge and every link comes up.
  const auto* port = h.host("orders")->on(K::dds);
  EXPECT_NE(std::find(setup.begin(), setup.end(),
                      Command{"ip", "-n", h.line_netns, "link", "set", port->peer, "master", "br-dds", "up"}),
            setup.end());
  EXPECT_NE(std::find(setup.begin(), setup.end(),
                      Command{"ip", "-n", h.host("orders")->netns, "link", "set", "dds0", "up"}),
            setup.end());

  // Teardown deletes every namespace (their veths go with them), the bridges' last.
  const auto teardown = host_teardown_commands(h);
  ASSERT_EQ(teardown.size(), all.size());
  EXPECT_EQ(teardown.back(), (Command{"ip", "netns", "del", h.line_netns}));
  std::set<std::string> deleted;
  for (const auto& c : teardown) {
    deleted.insert(c.back());
  }
  EXPECT_EQ(deleted, std::set<std::string>(all.begin(), all.end()));
}

TEST(HostPlan, TheNamesComeFromTheRunDirectory) {
  EXPECT_EQ(hosts_prefix("/tmp/run-a"), hosts_prefix("/tmp/run-a"));
  EXPECT_EQ(hosts_prefix("/tmp/run-a"), hosts_prefix("/tmp/./run-a/"));
  EXPECT_NE(hosts_prefix("/tmp/run-a"), hosts_prefix("/tmp/run-b"));
  const auto prefix = hosts_prefix("/tmp/run-a");
  ASSERT_EQ(prefix.size(), 9U);
  EXPECT_TRUE(prefix.starts_with("sf-"));
  EXPECT_EQ(prefix.find_first_not_of("0123456789abcdef", 3), std::string::npos) << prefix;
}

TEST(HostPlan, ProcessesRunInTheirNamespacesAndThePlantServesOnItsInterfaces) {
  sf::testing::TempDir dir;
  auto plan = hosts_plan(dir.path());
  ASSERT_TRUE(plan) << plan.error().describe();
  for (const auto& p : plan->processes) {
    const auto* host = plan->host_of(p);
    ASSERT_NE(host, nullptr) << p.name;
    ASSERT_GE(p.argv.size(), 5U);
    EXPECT_EQ(std::vector<std::string>(p.argv.begin(), p.argv.begin() + 5),
              (std::vector<std::string>{"ip", "netns", "exec", host->netns, "/bin/sh"}))
        << p.name;
  }
  const auto& plant = *find(*plan, "plant");
  EXPECT_TRUE(contains(plant.argv, {"--modbus-host", "10.77.1.1", "--control-host", "10.77.1.1"}));
  const auto robot_end = plan->hosts->host("plant")->on(K::ethercat)->name;
  EXPECT_TRUE(contains(plant.argv, {"--ecat-iface", "scara-robot-1=" + robot_end}));
  EXPECT_EQ(
      in_namespace(*plan->hosts->host("cloud"), {"prog", "x"}),
      (std::vector<std::string>{"ip", "netns", "exec", plan->hosts->host("cloud")->netns, "prog", "x"}));
}

TEST(HostPlan, TheConfigurationsNameEachProcesssInterfacesAndAddresses) {
  sf::testing::TempDir dir;
  auto plan = hosts_plan(dir.path());
  ASSERT_TRUE(plan) << plan.error().describe();
  const auto& h = *plan->hosts;
  const auto plant_end = h.host("plant")->on(K::ethercat)->name;
  const auto endpoints =
      parse_plant_endpoints(line_rig::endpoints_line(plan->layout, 1502, 0, "10.77.1.1", plant_end));
  ASSERT_TRUE(endpoints) << endpoints.error().describe();
  ASSERT_TRUE(write_controller_configs(*plan, *endpoints));

  auto robot = load_machine_config(find(*plan, "scara-robot-1")->config);
  ASSERT_TRUE(robot) << robot.error().describe();
  EXPECT_EQ(robot->config.ethercat.link, "ecat0");
  EXPECT_EQ(robot->config.controller.dds.interface, "dds0");
  EXPECT_EQ(robot->config.controller.opcua_host, "10.77.3.2");
  for (const auto* name : {"conveyor1", "uploader", "denso"}) {
    auto gateway = load_gateway_config(find(*plan, name)->config);
    ASSERT_TRUE(gateway) << gateway.error().describe();
    EXPECT_EQ(gateway->config.modbus.host, "10.77.1.1") << name;
    EXPECT_EQ(gateway->config.controller.dds.interface, "dds0") << name;
    EXPECT_EQ(gateway->config.controller.opcua_host, h.host(name)->address(K::opcua)) << name;
  }
  auto service = load_order_service_config(find(*plan, "orders")->config);
  ASSERT_TRUE(service) << service.error().describe();
  EXPECT_EQ(service->config.service.dds.interface, "dds0");
  EXPECT_EQ(service->config.service.opcua_host, h.host("orders")->address(K::opcua));

  // The cloud reads every server at its OPC UA address and serves its own on its address.
  const auto cloud = YAML::Load(cloud_config_yaml(*plan));
  EXPECT_EQ(cloud["aggregating_server"]["host"].as<std::string>(), h.host("cloud")->address(K::opcua));
  std::set<std::string> urls;
  for (const auto& s : cloud["servers"]) {
    urls.insert(s["url"].as<std::string>());
  }
  std::set<std::string> expected;
  for (const auto& p : plan->processes) {
    if (p.opcua_port != 0) {
      expected.insert(fmt::format("opc.tcp://{}:{}", h.host(p.name)->address(K::opcua), p.opcua_port));
    }
  }
  EXPECT_EQ(urls, expected);
  EXPECT_EQ(urls.size(), 11U);  // 10 controllers and the order service

  // Without its segment on a raw interface, the robot's configuration cannot be written.
  auto udp = parse_plant_endpoints(line_rig::endpoints_line(plan->layout, 1502, 1980, "10.77.1.1"));
  ASSERT_TRUE(udp);
  auto missing = controller_config_yaml(*plan, *find(*plan, "scara-robot-1"), *udp);
  ASSERT_FALSE(missing);
  EXPECT_NE(missing.error().message.find("ethercat-raw"), std::string::npos) << missing.error().message;
}

TEST(HostPlan, PlansThatCannotBeMadeAreRefused) {
  sf::testing::TempDir dir;
  auto plan = hosts_plan(dir.path());
  ASSERT_TRUE(plan) << plan.error().describe();
  auto processes = plan->processes;
  auto refused = plan_hosts("sf-Bad", processes);
  ASSERT_FALSE(refused);
  EXPECT_NE(refused.error().message.find("sf-Bad"), std::string::npos);
  EXPECT_FALSE(plan_hosts(std::string(40, 'a'), processes));

  // A smart robot needs the plant's namespace for the other end of its cable.
  std::swap(processes[0], processes[1]);
  refused = plan_hosts("sf-x", processes);
  ASSERT_FALSE(refused);
  EXPECT_NE(refused.error().message.find("scara-robot-1"), std::string::npos) << refused.error().message;

  // A /24 per network: at most 253 members.
  std::vector<LineProcess> many(254, plan->processes.back());
  for (std::size_t i = 0; i < many.size(); ++i) {
    many[i].name = fmt::format("p{}", i);
  }
  refused = plan_hosts("sf-x", many);
  ASSERT_FALSE(refused);
  EXPECT_NE(refused.error().message.find("254"), std::string::npos) << refused.error().message;
  many.pop_back();
  EXPECT_TRUE(plan_hosts("sf-x", many));

  // A process name that cannot name a namespace.
  processes = plan->processes;
  processes.back().name = "a/b";
  EXPECT_FALSE(plan_hosts("sf-x", processes));
}

// Runs a command to its end; its output (empty when it failed).
std::string output_of(std::vector<std::string> argv) {
  ProcessOptions o;
  o.argv = std::move(argv);
  o.in = Stdio::null();
  o.err = Stdio::null();
  auto done = Process::run(std::move(o), 10s);
  return done && done->status.success() ? done->out : std::string();
}

// The executor against the kernel: needs root (network namespaces), skipped otherwise.
class HostNetworksTest : public ::testing::Test {
 protected:
  void SetUp() override {
    if (auto st = hosts_supported(); !st) {
      GTEST_SKIP() << st.error().message;
    }
    auto p = hosts_plan(dir_.path());
    ASSERT_TRUE(p) << p.error().describe();
    // The plant and the smart robot only: a cable and the field, DDS and OPC UA networks.
    std::vector<LineProcess> two(p->processes.begin(), p->processes.begin() + 2);
    auto hosts = plan_hosts(fmt::format("sf-t{:x}", ::getpid()), two);
    ASSERT_TRUE(hosts) << hosts.error().describe();
    plan_ = std::move(*hosts);
  }
  void TearDown() override {
    for (const auto& ns : existing_namespaces(plan_.namespaces())) {
      output_of({"ip", "netns", "del", ns});
    }
  }
  static std::string links(const std::string& netns) { return output_of({"ip", "-n", netns, "-o", "link"}); }

  sf::testing::TempDir dir_;
  HostPlan plan_;
};

TEST_F(HostNetworksTest, MakesThePlanAndRemovesIt) {
  auto made = HostNetworks::create(plan_);
  ASSERT_TRUE(made) << made.error().describe();
  EXPECT_EQ(existing_namespaces(plan_.namespaces()), plan_.namespaces());
  const auto robot = links(plan_.hosts[1].netns);
  EXPECT_NE(robot.find("ecat0@"), std::string::npos) << robot;
  EXPECT_NE(robot.find("dds0@"), std::string::npos) << robot;
  EXPECT_NE(links(plan_.line_netns).find("master br-dds"), std::string::npos) << links(plan_.line_netns);
  EXPECT_TRUE((*made)->remove());
  EXPECT_TRUE(existing_namespaces(plan_.namespaces()).empty());
  EXPECT_TRUE((*made)->remove());  // idempotent
}

TEST_F(HostNetworksTest, AFailedSetupRemovesWhatItMade) {
  plan_.hosts[1].interfaces.back().peer = "a-name-longer-than-ifnamsiz";
  auto made = HostNetworks::create(plan_);
  ASSERT_FALSE(made);
  EXPECT_NE(made.error().message.find("a-name-longer-than-ifnamsiz"), std::string::npos)
      << made.error().message;
  EXPECT_TRUE(existing_namespaces(plan_.namespaces()).empty());
}

TEST_F(HostNetworksTest, NamespacesACrashedRunLeftAreRemovedFirst) {
  output_of({"ip", "netns", "add", plan_.hosts[0].netns});
  ASSERT_EQ(existing_namespaces({plan_.hosts[0].netns}).size(), 1U);
  std::vector<std::string> removed;
  auto made = HostNetworks::create(plan_, &removed);
  ASSERT_TRUE(made) << made.error().describe();
  EXPECT_EQ(removed, std::vector<std::string>{plan_.hosts[0].netns});
  EXPECT_NE(links(plan_.hosts[0].netns).find("field0@"), std::string::npos);
}

TEST_F(HostNetworksTest, CodeRunsInANamespaceAndTheThreadComesBack) {
  auto made = HostNetworks::create(plan_);
  ASSERT_TRUE(made) << made.error().describe();
  const auto own = fs::read_symlink("/proc/thread-self/ns/net");
  fs::path inside;
  ASSERT_TRUE(
      with_netns(plan_.hosts[0].netns, [&] { inside = fs::read_symlink("/proc/thread-self/ns/net"); }));
  EXPECT_NE(inside, own);
  EXPECT_EQ(fs::read_symlink("/proc/thread-self/ns/net"), own);
  EXPECT_FALSE(with_netns("sf-no-such-namespace", [] {}));
}

}  // namespace
}  // namespace sf::factory
