// The knowledge loop inside the gateway: an order service's OPC UA server publishes inspections
// and a machine's fault text; the gateway subscribes, the loop reasons, and the alarms land in the
// historian as events of the server "knowledge", raised and cleared.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <mutex>

#include "counter_server.hpp"
#include "sf/cloud/gateway.hpp"
#include "sf/line/inspection.hpp"

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

 private:
  ua::NodeId object(srv::AddressSpace& space, const std::string& name, const ua::NodeId& parent) const {
    srv::ObjectSpec o;
    o.node_id = ua::NodeId(ns_, ua::String(name + ".Object"));
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

TEST(GatewayKnowledge, AMismatchedBoxAndAMachineFaultBecomeAlarmsInTheHistorian) {
  ShopFloorServer shop_floor;
  ASSERT_TRUE(shop_floor.ok());
  TempDir dir;
  ServerConfig server =
      server_config("shop-floor", "opc.tcp://127.0.0.1:" + std::to_string(shop_floor.port()),
                    {path_rule("/Objects/OrderService", 1), path_rule("/Objects/Machines", 2)});
  server.publishing_interval_ms = 20;
  server.sampling_interval_ms = 10;
  GatewayConfig config = test::sqlite_gateway(dir, server);
  config.knowledge = KnowledgeConfig{};  // the built-in layout, ontology and rules
  auto gateway = Gateway::create(config);
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
