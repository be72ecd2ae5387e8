// The knowledge loop inside the gateway: an order service's OPC UA server publishes inspections,
// a machine's fault text, a robot's temperature and an axis position; the gateway subscribes, the
// loop reasons, and the alarms land in the historian as events of the server "knowledge", raised
// and cleared, and reach node-opcua's client as condition events of the aggregating server.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <mutex>
#include <set>

#include "counter_server.hpp"
#include "sf/cloud/gateway.hpp"
#include "sf/line/inspection.hpp"
#include "sf/opcua/units.hpp"
#include "sf/testing/node_peer.hpp"

namespace sf::cloud {
namespace {

namespace ua = sf::opcua;
namespace srv = sf::opcua::server;
using test::eventually;
using test::path_rule;
using test::server_config;
using test::TempDir;

// Objects/OrderService/LastInspection and Objects/Machines/Conveyor3/Fault, String variables
// the test sets.
class ShopFloorServer {
 public:
  ShopFloorServer() {
    srv::ServerConfig config;
    config.transport.host = "127.0.0.1";
    config.transport.port = 0;
    config.advertised_host = "127.0.0.1";
    server_ = std::make_unique<srv::Server>(config);
    server_->with_address_space([this](srv::AddressSpace& space) {
      ns_ = space.add_namespace("urn:smartfactory:test:shop-floor");
      const ua::NodeId orders = object(space, "OrderService", ua::NodeId(0, ua::id::ObjectsFolder));
      const ua::NodeId machines = object(space, "Machines", ua::NodeId(0, ua::id::ObjectsFolder));
      const ua::NodeId conveyor = object(space, "Conveyor3", machines);
      variable(space, "LastInspection", orders);
      variable(space, "Fault", conveyor);
      // Tags as a controller publishes them: SI values with their EngineeringUnits.
      const ua::NodeId denso = object(space, "Denso", machines);
      tag(space, "robot.temperature", object(space, "Tags", denso, "Denso"),
          ua::unece_unit("CEL", "°C", "degree Celsius"));
      const ua::NodeId robot = object(space, "ScaraRobot1", machines);
      tag(space, "axis1.position", object(space, "Tags", robot, "ScaraRobot1"),
          ua::unece_unit("C81", "rad", "radian"));
    });
    ok_ = server_->start().ok();
  }
  [[nodiscard]] bool ok() const { return ok_; }
  [[nodiscard]] std::uint16_t port() const { return server_->port(); }
  [[nodiscard]] std::size_t monitored_items() const { return server_->monitored_item_count(); }
  void set(const std::string& name, const std::string& text) {
    server_->with_address_space([&](srv::AddressSpace& space) {
      (void)space.set_value(ua::NodeId(ns_, ua::String(name)), ua::DataValue(ua::Variant(ua::String(text))));
    });
  }
  void set(const std::string& name, double v) {
    server_->with_address_space([&](srv::AddressSpace& space) {
      (void)space.set_value(ua::NodeId(ns_, ua::String(name)), ua::DataValue(ua::Variant(v)));
    });
  }

 private:
  ua::NodeId object(srv::AddressSpace& space, const std::string& name, const ua::NodeId& parent,
                    const std::string& owner = {}) const {
    srv::ObjectSpec o;
    o.node_id = ua::NodeId(ns_, ua::String(owner + name + ".Object"));
    o.browse_name = ua::QualifiedName(ns_, name);
    o.parent = parent;
    o.reference_type = ua::NodeId(
        0, parent == ua::NodeId(0, ua::id::ObjectsFolder) ? ua::id::Organizes : ua::id::HasComponent);
    (void)space.add_object(o);
    return o.node_id;
  }
  void variable(srv::AddressSpace& space, const std::string& name, const ua::NodeId& parent) const {
    srv::VariableSpec v;
    v.node_id = ua::NodeId(ns_, ua::String(name));
    v.browse_name = ua::QualifiedName(ns_, name);
    v.parent = parent;
    v.data_type = ua::NodeId(0, ua::id::String);
    v.value = ua::DataValue(ua::Variant(ua::String("")));
    (void)space.add_variable(v);
  }
  // A Double variable with its EngineeringUnits property (OPC 10000-8 §5.6.3).
  void tag(srv::AddressSpace& space, const std::string& name, const ua::NodeId& parent,
           const ua::EUInformation& unit) const {
    srv::VariableSpec v;
    v.node_id = ua::NodeId(ns_, ua::String(name));
    v.browse_name = ua::QualifiedName(ns_, name);
    v.parent = parent;
    v.reference_type = ua::NodeId(0, ua::id::HasComponent);
    v.data_type = ua::NodeId(0, ua::id::Double);
    v.value = ua::DataValue(ua::Variant(0.0));
    (void)space.add_variable(v);
    srv::VariableSpec eu;
    eu.node_id = ua::NodeId(ns_, ua::String(name + ".EngineeringUnits"));
    eu.browse_name = ua::QualifiedName(0, "EngineeringUnits");
    eu.parent = v.node_id;
    eu.reference_type = ua::NodeId(0, ua::id::HasProperty);
    eu.type_definition = ua::NodeId(0, ua::id::PropertyType);
    eu.data_type = ua::NodeId(0, ua::id::EUInformation);
    eu.value = ua::DataValue(ua::Variant(ua::ExtensionObject::make(unit)));
    (void)space.add_variable(eu);
  }

  std::unique_ptr<srv::Server> server_;
  std::uint16_t ns_ = 0;
  bool ok_ = false;
};

std::vector<historian::Event> knowledge_events(historian::Store& store) {
  historian::EventQuery q;
  q.from = historian::from_micros(0);
  q.to = historian::from_micros(INT64_MAX / 2);
  q.server = std::string(kKnowledgeServer);
  auto events = store.read_events(q);
  return events ? *events : std::vector<historian::Event>{};
}

// A gateway of the shop floor with the knowledge loop (the built-in layout, ontology and rules),
// subscribed to the machines' variables down to `depth` levels below Machines.
GatewayConfig knowledge_gateway(const TempDir& dir, const ShopFloorServer& shop_floor, unsigned depth) {
  ServerConfig server =
      server_config("shop-floor", "opc.tcp://127.0.0.1:" + std::to_string(shop_floor.port()),
                    {path_rule("/Objects/OrderService", 1), path_rule("/Objects/Machines", depth)});
  server.publishing_interval_ms = 20;
  server.sampling_interval_ms = 10;
  GatewayConfig config = test::sqlite_gateway(dir, server);
  config.knowledge = KnowledgeConfig{};
  return config;
}

TEST(GatewayKnowledge, AMismatchedBoxAndAMachineFaultBecomeAlarmsInTheHistorian) {
  ShopFloorServer shop_floor;
  ASSERT_TRUE(shop_floor.ok());
  TempDir dir;
  auto gateway = Gateway::create(knowledge_gateway(dir, shop_floor, 2));  // Fault, not the tags
  ASSERT_TRUE(gateway) << gateway.error().describe();
  ASSERT_NE((*gateway)->knowledge(), nullptr);
  ASSERT_TRUE((*gateway)->start());
  ASSERT_TRUE(eventually([&] { return shop_floor.monitored_items() == 2; }));

  const line::InspectionRecord bad{"alice-1", 7, "small-box", {{"gummy", 4}}, {{"gummy", 3}}, 47.5, 20.0};
  shop_floor.set("LastInspection", line::format_inspection(bad));
  shop_floor.set("Fault", "jam (fault 1)");
  ASSERT_TRUE(eventually([&] { return knowledge_events((*gateway)->store()).size() == 2; }))
      << knowledge_events((*gateway)->store()).size() << " alarms; "
      << (*gateway)->knowledge()->status().last_error;
  shop_floor.set("Fault", "");
  ASSERT_TRUE(eventually([&] { return knowledge_events((*gateway)->store()).size() == 3; }));

  std::map<std::string, std::vector<bool>> by_rule;  // rule → raised (true) / cleared, in order
  for (const auto& e : knowledge_events((*gateway)->store())) {
    const auto fields = nlohmann::json::parse(e.fields);
    by_rule[fields["rule"].get<std::string>()].push_back(fields["active"].get<bool>());
    if (fields["rule"] == "contentMismatch") {
      EXPECT_EQ(e.message, "gummy bear: ordered 4, the box holds 3");
      EXPECT_EQ(e.source_name, "Box_alice-1_7");
      EXPECT_FALSE(fields["facts"].empty());
    }
  }
  EXPECT_EQ(by_rule["contentMismatch"], std::vector<bool>{true});
  EXPECT_EQ(by_rule["fault"], (std::vector<bool>{true, false}));
  EXPECT_EQ((*gateway)->knowledge()->active_alarms().size(), 1U);
  (*gateway)->stop();
}

// node-opcua's client (tests/peers/opcua/event_client.mjs) subscribed to the aggregating
// server's events: one JSON line per event.
class EventClient {
 public:
  // Starts the client and waits until its event monitored item exists.
  Status start(std::uint16_t port) {
    ProcessOptions o;
    o.argv = {testing::find_node()->string(),
              (testing::source_dir() / "tests" / "peers" / "opcua" / "event_client.mjs").string(),
              "opc.tcp://127.0.0.1:" + std::to_string(port)};
    o.cwd = testing::source_dir();
    o.in = Stdio::pipe();
    o.out = Stdio::pipe();
    o.err = Stdio::inherit();
    auto started = Process::spawn(std::move(o));
    if (!started) {
      return started.error();
    }
    process_ = std::move(*started);
    auto ready = process_.wait_for_line([](const std::string& line) { return line == "SUBSCRIBED"; },
                                        std::chrono::seconds(90));
    if (!ready) {
      return ready.error();
    }
    return {};
  }
  ~EventClient() { process_.close_and_wait(std::chrono::seconds(10)); }

  // Asks for a ConditionRefresh; its answer is a line {"refresh": <StatusCode>}.
  Status refresh() { return process_.write_stdin("REFRESH\n"); }
  // The next line, whatever it reports.
  std::optional<nlohmann::json> next_line() {
    if (!pending_.empty()) {
      auto e = pending_.front();
      pending_.erase(pending_.begin());
      return e;
    }
    auto line = process_.read_line(std::chrono::seconds(30));
    if (!line) {
      return std::nullopt;
    }
    auto e = nlohmann::json::parse(*line, nullptr, false);
    return e.is_discarded() ? std::nullopt : std::optional<nlohmann::json>(e);
  }

  // The next event of the condition `rule`; events of other conditions are kept for later.
  std::optional<nlohmann::json> next(std::string_view rule) {
    for (auto it = pending_.begin(); it != pending_.end(); ++it) {
      if ((*it)["conditionName"] == rule) {
        auto e = *it;
        pending_.erase(it);
        return e;
      }
    }
    while (true) {
      auto line = process_.read_line(std::chrono::seconds(30));
      if (!line) {
        return std::nullopt;
      }
      auto e = nlohmann::json::parse(*line, nullptr, false);
      if (e.is_discarded()) {
        continue;
      }
      if (e["conditionName"] == rule) {
        return e;
      }
      pending_.push_back(std::move(e));
    }
  }

 private:
  Process process_;
  std::vector<nlohmann::json> pending_;
};

// A raise: active, unacknowledged, retained, with the rule's message.
void expect_raised(const std::optional<nlohmann::json>& e, const std::string& message) {
  ASSERT_TRUE(e.has_value()) << "no event";
  EXPECT_EQ((*e)["eventType"], "ns=0;i=2915") << e->dump();  // AlarmConditionType
  EXPECT_EQ((*e)["message"], message) << e->dump();
  EXPECT_EQ((*e)["activeState"], "Active") << e->dump();
  EXPECT_EQ((*e)["activeStateId"], true) << e->dump();
  EXPECT_EQ((*e)["ackedStateId"], false) << e->dump();
  EXPECT_EQ((*e)["retain"], true) << e->dump();
  EXPECT_EQ((*e)["severity"], 700) << e->dump();
  // ConditionId, selected as the NodeId attribute of ConditionType: the alarm's id.
  const std::string condition = (*e)["conditionId"].is_string() ? (*e)["conditionId"].get<std::string>() : "";
  EXPECT_NE(condition.find(";s=knowledge/" + (*e)["conditionName"].get<std::string>() + "-"),
            std::string::npos)
      << e->dump();
}

void expect_cleared(const std::optional<nlohmann::json>& e, const nlohmann::json& raised) {
  ASSERT_TRUE(e.has_value()) << "no event";
  EXPECT_EQ((*e)["activeState"], "Inactive") << e->dump();
  EXPECT_EQ((*e)["activeStateId"], false) << e->dump();
  EXPECT_EQ((*e)["conditionId"], raised["conditionId"]) << e->dump();
  EXPECT_EQ((*e)["sourceName"], raised["sourceName"]) << e->dump();
  EXPECT_EQ((*e)["message"], "cleared: " + raised["message"].get<std::string>()) << e->dump();
}

TEST(GatewayKnowledge, NodeOpcuaReceivesTheAlarmsAsConditionEventsOfTheAggregatingServer) {
  if (auto why = testing::node_unavailable()) {
    GTEST_SKIP() << *why;
  }
  ShopFloorServer shop_floor;
  ASSERT_TRUE(shop_floor.ok());
  TempDir dir;
  GatewayConfig config = knowledge_gateway(dir, shop_floor, 3);
  config.aggregating_server.enabled = true;
  config.aggregating_server.host = "127.0.0.1";
  config.aggregating_server.port = 0;
  auto gateway = Gateway::create(config);
  ASSERT_TRUE(gateway) << gateway.error().describe();
  ASSERT_TRUE((*gateway)->start());
  ASSERT_TRUE(eventually([&] { return shop_floor.monitored_items() == 4; })) << shop_floor.monitored_items();
  EventClient client;
  const Status subscribed = client.start((*gateway)->status().aggregating_port);
  ASSERT_TRUE(subscribed) << subscribed.error().describe();

  // Each value goes back only once the client has seen the raise: no value is sampled away.
  shop_floor.set("robot.temperature", 74.5);  // °C; the DENSO's maximum is 70.0
  const auto hot = client.next("temperatureHigh");
  expect_raised(hot, "temperature 74.5 above the maximum 70.0");
  EXPECT_EQ((*hot)["sourceName"], "Denso");
  shop_floor.set("robot.temperature", 65.0);
  expect_cleared(client.next("temperatureHigh"), *hot);

  shop_floor.set("axis1.position", 2.7);  // rad: 154.699°, the travel is -149.0..149.0°
  const auto out = client.next("axisTravel");
  expect_raised(out, "position 154.699 outside -149.0..149.0");
  EXPECT_EQ((*out)["sourceName"], "ScaraRobot1Axis1");
  shop_floor.set("axis1.position", 0.5);
  expect_cleared(client.next("axisTravel"), *out);

  line::InspectionRecord box{"dora-1", 3, "small-box", {{"toffee", 4}}, {{"toffee", 3}}, 72.0, 20.0};
  shop_floor.set("LastInspection", line::format_inspection(box));
  const auto short_one = client.next("contentMismatch");
  expect_raised(short_one, "toffee: ordered 4, the box holds 3");
  box.counted["toffee"] = 4;  // refilled and inspected again
  shop_floor.set("LastInspection", line::format_inspection(box));
  expect_cleared(client.next("contentMismatch"), *short_one);

  // Cleared, not yet acknowledged: retained until an operator acknowledges it.
  auto* knowledge = (*gateway)->knowledge();
  ASSERT_EQ(knowledge->retained_alarms().size(), 3U);
  std::string id;
  for (const auto& a : knowledge->retained_alarms()) {
    id = a.rule == "temperatureHigh" ? a.id : id;
  }
  ASSERT_TRUE(knowledge->acknowledge(id, "olga", "checked the fan"));
  const auto acked = client.next("temperatureHigh");
  ASSERT_TRUE(acked.has_value());
  EXPECT_EQ((*acked)["ackedStateId"], true) << acked->dump();
  EXPECT_EQ((*acked)["activeStateId"], false) << acked->dump();
  EXPECT_EQ((*acked)["retain"], false) << acked->dump();
  EXPECT_EQ((*acked)["conditionId"], (*hot)["conditionId"]);

  // ConditionRefresh (OPC 10000-9 §5.5.7): the two alarms still retained (cleared, not
  // acknowledged) between the refresh's start and end.
  ASSERT_TRUE(client.refresh());
  std::vector<nlohmann::json> refreshed;
  for (int i = 0; i < 5; ++i) {
    auto line = client.next_line();
    ASSERT_TRUE(line.has_value()) << "line " << i;
    refreshed.push_back(*line);
  }
  std::erase_if(refreshed, [](const nlohmann::json& j) {
    EXPECT_FALSE(j.contains("refresh") && j["refresh"] != "Good") << j.dump();
    return j.contains("refresh");
  });
  ASSERT_EQ(refreshed.size(), 4U);
  EXPECT_EQ(refreshed[0]["eventType"], "ns=0;i=2787") << refreshed[0].dump();  // RefreshStartEventType
  EXPECT_EQ(refreshed[3]["eventType"], "ns=0;i=2788") << refreshed[3].dump();  // RefreshEndEventType
  std::set<std::string> conditions;
  for (std::size_t i = 1; i <= 2; ++i) {
    conditions.insert(refreshed[i]["conditionName"].get<std::string>());
    EXPECT_EQ(refreshed[i]["retain"], true) << refreshed[i].dump();
    EXPECT_EQ(refreshed[i]["activeStateId"], false) << refreshed[i].dump();
  }
  EXPECT_EQ(conditions, (std::set<std::string>{"axisTravel", "contentMismatch"}));
  (*gateway)->stop();
  // The historian holds the same seven events.
  EXPECT_EQ(knowledge_events((*gateway)->store()).size(), 7U);
}

TEST(GatewayKnowledge, AKnowledgeSectionThatCannotBeReadStopsTheGatewayAtCreate) {
  TempDir dir;
  GatewayConfig config =
      test::sqlite_gateway(dir, server_config("a", "opc.tcp://127.0.0.1:1", {path_rule("/Objects")}));
  config.knowledge = KnowledgeConfig{};
  config.knowledge->rules = dir.path() / "missing.rules";
  auto gateway = Gateway::create(config);
  ASSERT_FALSE(gateway);
  EXPECT_NE(gateway.error().describe().find("missing.rules"), std::string::npos)
      << gateway.error().describe();
}

}  // namespace
}  // namespace sf::cloud
