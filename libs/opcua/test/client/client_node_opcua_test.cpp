// Our client against a node-opcua server with the demo model: it browses, reads, writes, calls
// and subscribes against a server that is not ours. Skipped when node
// or node_modules is missing.
#include <gtest/gtest.h>

#include <algorithm>
#include <memory>

#include "node_server.hpp"
#include "sf/opcua/client/client.hpp"

namespace sf::opcua {
namespace {

using test::Collector;
using test::NodeServer;

ClientConfig config_for(const std::string& url) {
  ClientConfig config;
  config.endpoint_url = url;
  config.request_timeout = std::chrono::milliseconds(5000);
  config.reconnect_min = std::chrono::milliseconds(100);
  config.reconnect_max = std::chrono::milliseconds(1000);
  return config;
}

class NodeOpcuaTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    if (test::node_unavailable()) {
      return;
    }
    server_ = new NodeServer();
    if (!server_->start()) {
      delete server_;
      server_ = nullptr;
    }
  }
  static void TearDownTestSuite() {
    delete server_;
    server_ = nullptr;
  }

  void SetUp() override {
    if (auto why = test::node_unavailable()) {
      GTEST_SKIP() << *why;
    }
    ASSERT_NE(server_, nullptr) << "the node-opcua server did not start";
    client_ = std::make_unique<SyncClient>(config_for(server_->url()));
    const Status connected = client_->connect();
    ASSERT_TRUE(connected.ok()) << connected.error().describe();
    auto ns = client_->namespace_index("urn:smartfactory:demo");
    ASSERT_TRUE(ns.ok()) << ns.error().describe();
    ns_ = *ns;
  }
  void TearDown() override {
    if (client_) {
      client_->disconnect();
      EXPECT_EQ(client_->state(), ClientState::Disconnected);
    }
  }

  [[nodiscard]] NodeId demo(const std::string& name) const { return NodeId(ns_, String(name)); }

  static NodeServer* server_;
  std::unique_ptr<SyncClient> client_;
  std::uint16_t ns_ = 0;
};

NodeServer* NodeOpcuaTest::server_ = nullptr;

TEST_F(NodeOpcuaTest, ConnectsAndIsConnected) {
  EXPECT_EQ(client_->state(), ClientState::Connected);
  EXPECT_GE(ns_, 1);
}

TEST_F(NodeOpcuaTest, BrowseObjectsFindsDemo) {
  auto references = client_->browse_children(NodeId(0, id::ObjectsFolder));
  ASSERT_TRUE(references.ok()) << references.error().describe();
  const auto found = std::find_if(references->begin(), references->end(), [&](const ReferenceDescription& r) {
    return r.browse_name.name == "Demo" && r.browse_name.namespace_index == ns_;
  });
  ASSERT_NE(found, references->end());
  EXPECT_EQ(found->node_id.node_id, demo("Demo"));
  EXPECT_EQ(found->node_class, NodeClass::Object);

  auto children = client_->browse_children(demo("Demo"));
  ASSERT_TRUE(children.ok()) << children.error().describe();
  std::vector<std::string> names;
  for (const auto& r : *children) {
    names.push_back(r.browse_name.name.str());
  }
  for (const char* expected : {"Temperature", "Counter", "Multiply"}) {
    EXPECT_NE(std::find(names.begin(), names.end(), expected), names.end()) << expected;
  }
}

TEST_F(NodeOpcuaTest, BrowseFollowsContinuationPoints) {
  // Namespace 0's type hierarchy is large enough that node-opcua pages it with the
  // server-chosen maximum; the client must return every reference either way.
  auto references = client_->browse_children(NodeId(0, id::Server));
  ASSERT_TRUE(references.ok()) << references.error().describe();
  EXPECT_GT(references->size(), 5U);
}

TEST_F(NodeOpcuaTest, ReadsTemperature) {
  auto value = client_->read_value(demo("Demo.Temperature"));
  ASSERT_TRUE(value.ok()) << value.error().describe();
  ASSERT_NE(value->value.get_if<double>(), nullptr) << to_string(value->value);
  EXPECT_GT(*value->value.get_if<double>(), 10.0);
  EXPECT_LT(*value->value.get_if<double>(), 30.0);
  EXPECT_FALSE(value->source_timestamp.is_min());
}

TEST_F(NodeOpcuaTest, WritesAndReadsCounter) {
  ASSERT_TRUE(client_->write_value(demo("Demo.Counter"), Variant(std::int32_t{41})).ok());
  auto value = client_->read_value(demo("Demo.Counter"));
  ASSERT_TRUE(value.ok()) << value.error().describe();
  ASSERT_NE(value->value.get_if<std::int32_t>(), nullptr);
  EXPECT_EQ(*value->value.get_if<std::int32_t>(), 41);

  // Temperature is read-only: the write comes back per item.
  WriteValue write;
  write.node_id = demo("Demo.Temperature");
  write.attribute_id = attribute_id::Value;
  write.value = DataValue(Variant(1.0));
  auto results = client_->write({write});
  ASSERT_TRUE(results.ok()) << results.error().describe();
  ASSERT_EQ(results->size(), 1U);
  EXPECT_TRUE(results->front().is_bad());
}

TEST_F(NodeOpcuaTest, CallsMultiply) {
  auto outputs = client_->call_method(demo("Demo"), demo("Demo.Multiply"), {Variant(6.0), Variant(7.0)});
  ASSERT_TRUE(outputs.ok()) << outputs.error().describe();
  ASSERT_EQ(outputs->size(), 1U);
  ASSERT_NE(outputs->front().get_if<double>(), nullptr);
  EXPECT_DOUBLE_EQ(*outputs->front().get_if<double>(), 42.0);
}

TEST_F(NodeOpcuaTest, UnknownNodeGivesBadNodeIdUnknownPerItem) {
  auto values = client_->read({value_of(demo("Demo.DoesNotExist")), value_of(demo("Demo.Counter"))});
  ASSERT_TRUE(values.ok()) << values.error().describe();
  ASSERT_EQ(values->size(), 2U);
  EXPECT_EQ((*values)[0].status, status::BadNodeIdUnknown);
  EXPECT_TRUE((*values)[1].status.is_good());

  auto single = client_->read_value(demo("Demo.DoesNotExist"));
  ASSERT_FALSE(single.ok());
  EXPECT_EQ(status_of(single.error()), status::BadNodeIdUnknown);
}

TEST_F(NodeOpcuaTest, TranslatesBrowsePath) {
  BrowsePath path;
  path.starting_node = NodeId(0, id::ObjectsFolder);
  RelativePathElement element;
  element.reference_type_id = NodeId(0, id::HierarchicalReferences);
  element.include_subtypes = true;
  element.target_name = QualifiedName(ns_, "Demo");
  path.relative_path.elements.push_back(element);
  element.target_name = QualifiedName(ns_, "Counter");
  path.relative_path.elements.push_back(element);
  auto results = client_->translate({path});
  ASSERT_TRUE(results.ok()) << results.error().describe();
  ASSERT_EQ(results->size(), 1U);
  ASSERT_TRUE(results->front().status_code.is_good()) << to_string(results->front().status_code);
  ASSERT_EQ(results->front().targets.size(), 1U);
  EXPECT_EQ(results->front().targets.front().target_id.node_id, demo("Demo.Counter"));
}

TEST_F(NodeOpcuaTest, GetsEndpointsWithAndWithoutSession) {
  auto endpoints = client_->get_endpoints();
  ASSERT_TRUE(endpoints.ok()) << endpoints.error().describe();
  ASSERT_FALSE(endpoints->empty());
  EXPECT_EQ(endpoints->front().security_mode, MessageSecurityMode::None);

  SyncClient unconnected(config_for(server_->url()));
  auto again = unconnected.get_endpoints();
  ASSERT_TRUE(again.ok()) << again.error().describe();
  EXPECT_EQ(again->size(), endpoints->size());
}

// FindServers on a channel of its own (OPC 10000-4 §5.4.2): node-opcua's server describes itself
// with a discovery URL a client can connect to.
TEST_F(NodeOpcuaTest, FindsTheServerWithoutASession) {
  SyncClient unconnected(config_for(server_->url()));
  auto servers = unconnected.find_servers();
  ASSERT_TRUE(servers.ok()) << servers.error().describe();
  ASSERT_EQ(servers->size(), 1U);
  const ApplicationDescription& server = servers->front();
  EXPECT_EQ(server.application_type, ApplicationType::Server);
  EXPECT_FALSE(server.application_uri.view().empty());
  ASSERT_FALSE(server.discovery_urls.empty());
  EXPECT_TRUE(server.discovery_urls.front().view().starts_with("opc.tcp://"));
  auto none = unconnected.find_servers({"urn:nobody:here"});
  ASSERT_TRUE(none.ok()) << none.error().describe();
  EXPECT_TRUE(none->empty());
}

TEST_F(NodeOpcuaTest, SubscribesToTemperature) {
  auto subscription = client_->create_subscription({.publishing_interval_ms = 100});
  ASSERT_TRUE(subscription.ok()) << subscription.error().describe();
  Collector<double> values;
  MonitoringParameters parameters;
  parameters.sampling_interval = 100;
  parameters.queue_size = 10;
  parameters.discard_oldest = true;
  auto handle = client_->monitor_value(*subscription, value_of(demo("Demo.Temperature")), parameters,
                                       [&](const DataValue& value) {
                                         if (const auto* d = value.value.get_if<double>()) {
                                           values.add(*d);
                                         }
                                       });
  ASSERT_TRUE(handle.ok()) << handle.error().describe();
  ASSERT_TRUE(values.wait_for(4)) << "received " << values.size();
  auto received = values.values();
  std::sort(received.begin(), received.end());
  EXPECT_GE(std::unique(received.begin(), received.end()) - received.begin(), 3);
  EXPECT_TRUE(client_->delete_subscription(*subscription).ok());
}

TEST_F(NodeOpcuaTest, MonitorOnUnknownNodeFails) {
  auto subscription = client_->create_subscription({});
  ASSERT_TRUE(subscription.ok()) << subscription.error().describe();
  auto handle =
      client_->monitor_value(*subscription, value_of(demo("Demo.Nope")), {}, [](const DataValue&) {});
  ASSERT_FALSE(handle.ok());
  EXPECT_EQ(status_of(handle.error()), status::BadNodeIdUnknown);
}

TEST_F(NodeOpcuaTest, ReceivesEventsFromServerObject) {
  auto subscription = client_->create_subscription({.publishing_interval_ms = 100});
  ASSERT_TRUE(subscription.ok()) << subscription.error().describe();
  Collector<std::vector<Variant>> events;
  auto handle = client_->monitor_events(*subscription, NodeId(0, id::Server),
                                        select_event_fields({"EventId", "Message", "Severity"}),
                                        [&](const std::vector<Variant>& fields) { events.add(fields); });
  ASSERT_TRUE(handle.ok()) << handle.error().describe();
  auto raised = client_->call_method(demo("Demo"), demo("Demo.RaiseEvent"), {Variant("hello from the test")});
  ASSERT_TRUE(raised.ok()) << raised.error().describe();

  // The periodic "tick" events arrive too; wait until ours is among them.
  bool found = false;
  for (std::size_t n = 1; n <= 10 && !found; ++n) {
    ASSERT_TRUE(events.wait_for(n)) << "events received: " << events.size();
    const auto fields = events.values()[n - 1];
    ASSERT_EQ(fields.size(), 3U);
    EXPECT_NE(fields[0].get_if<ByteString>(), nullptr);  // EventId
    const auto* message = fields[1].get_if<LocalizedText>();
    ASSERT_NE(message, nullptr) << to_string(fields[1]);
    if (message->text == "hello from the test") {
      found = true;
      ASSERT_NE(fields[2].get_if<std::uint16_t>(), nullptr);
      EXPECT_EQ(*fields[2].get_if<std::uint16_t>(), 500);
    }
  }
  EXPECT_TRUE(found);
}

// OPC 10000-4 §6.7: the server process dies mid-subscription and a new one starts on the same
// port. The old session is gone, so the client creates a new session, re-creates the
// subscription and its item with the same client handle, and values keep arriving.
TEST(NodeOpcuaReconnectTest, ServerRestartMidSubscription) {
  if (auto why = test::node_unavailable()) {
    GTEST_SKIP() << *why;
  }
  NodeServer server;
  ASSERT_TRUE(server.start());
  SyncClient client(config_for(server.url()));
  Collector<ClientState> states;
  client.set_on_state([&](ClientState state, const Status&) { states.add(state); });
  ASSERT_TRUE(client.connect().ok());
  auto ns = client.namespace_index("urn:smartfactory:demo");
  ASSERT_TRUE(ns.ok());
  auto subscription = client.create_subscription({.publishing_interval_ms = 100});
  ASSERT_TRUE(subscription.ok());
  Collector<double> values;
  MonitoringParameters parameters;
  parameters.sampling_interval = 100;
  parameters.queue_size = 10;
  auto handle = client.monitor_value(*subscription, value_of(NodeId(*ns, String("Demo.Temperature"))),
                                     parameters, [&](const DataValue& value) {
                                       if (const auto* d = value.value.get_if<double>()) {
                                         values.add(*d);
                                       }
                                     });
  ASSERT_TRUE(handle.ok()) << handle.error().describe();
  ASSERT_TRUE(values.wait_for(3));

  const std::uint16_t port = server.port();
  server.kill();
  // Wait until the client noticed (state Reconnecting), then bring a new server up.
  ASSERT_TRUE(states.wait_until([](const std::vector<ClientState>& seen) {
    return !seen.empty() && seen.back() == ClientState::Reconnecting;
  }));
  const std::size_t received_before_restart = values.size();
  ASSERT_TRUE(server.start(port));
  ASSERT_EQ(server.port(), port);

  // New session, subscription and item re-created: values arrive again.
  ASSERT_TRUE(values.wait_for(received_before_restart + 3, std::chrono::seconds(30)))
      << "values after restart: " << values.size() - received_before_restart;
  EXPECT_TRUE(states.wait_until(
      [](const std::vector<ClientState>& seen) { return seen.back() == ClientState::Connected; }));
  EXPECT_EQ(client.state(), ClientState::Connected);

  // The same subscription handle still works.
  EXPECT_TRUE(client.unmonitor(*subscription, *handle).ok());
  EXPECT_TRUE(client.delete_subscription(*subscription).ok());
  client.disconnect();
}

}  // namespace
}  // namespace sf::opcua
