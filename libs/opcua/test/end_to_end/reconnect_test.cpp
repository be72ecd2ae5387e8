// Our client against our server over real sockets when the connection goes away (OPC 10000-4
// §6.7): a lost network keeps the session, and the notifications the server queued meanwhile
// arrive in order with none lost or repeated (Republish / Publish resume); a restarted server
// has forgotten the session, and the client re-creates session, subscription and monitored
// item with the same handles and keeps delivering.
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <memory>

#include "../collector.hpp"
#include "sf/opcua/client/client.hpp"
#include "sf/opcua/server/server.hpp"
#include "tcp_proxy.hpp"
#include "variables.hpp"

namespace sf::opcua {
namespace {

using namespace std::chrono_literals;
using test::Collector;

constexpr std::string_view kNamespace = "urn:smartfactory:test:reconnect";

// An Int32 variable the test sets; wait_sampled() returns once the server has read the value set
// last, so that its sample is in the monitored item's queue (no sleeping on timing).
class ObservedValue {
 public:
  explicit ObservedValue(std::int32_t initial) : value_(initial) {}
  void set(std::int32_t value) {
    value_ = value;
    ++generation_;
  }
  bool wait_sampled(std::chrono::milliseconds timeout = 10s) const {
    const auto until = std::chrono::steady_clock::now() + timeout;
    while (sampled_.load() < generation_.load()) {
      if (std::chrono::steady_clock::now() > until) {
        return false;
      }
      std::this_thread::sleep_for(1ms);
    }
    return true;
  }
  DataValue read() {
    const std::uint64_t generation = generation_.load();
    DataValue value(Variant(value_.load()));
    sampled_ = generation;
    return value;
  }

 private:
  std::atomic<std::int32_t> value_;
  std::atomic<std::uint64_t> generation_{0};
  std::atomic<std::uint64_t> sampled_{0};
};

std::unique_ptr<server::Server> start_server(std::uint16_t port,
                                             const std::shared_ptr<ObservedValue>& observed, NodeId& node) {
  server::ServerConfig config;
  config.transport.host = "127.0.0.1";
  config.transport.port = port;
  config.advertised_host = "127.0.0.1";
  auto s = std::make_unique<server::Server>(config);
  node = test::add_int32_variable(*s, kNamespace, "Observed", [observed] { return observed->read(); });
  EXPECT_TRUE(s->start().ok());
  return s;
}

ClientConfig client_config(std::uint16_t port) {
  ClientConfig config;
  config.endpoint_url = "opc.tcp://127.0.0.1:" + std::to_string(port);
  config.request_timeout = 2s;
  config.reconnect_min = 50ms;
  config.reconnect_max = 500ms;
  return config;
}

// Subscribes to node (sampling 10 ms, a queue long enough for an outage) and collects its values.
std::uint32_t subscribe(SyncClient& client, const NodeId& node, Collector<std::int32_t>& values,
                        SyncClient::SubscriptionId& subscription) {
  auto created = client.create_subscription({.publishing_interval_ms = 50});
  EXPECT_TRUE(created.ok());
  subscription = *created;
  MonitoringParameters parameters;
  parameters.sampling_interval = 10;
  parameters.queue_size = 1000;
  auto handle = client.monitor_value(subscription, value_of(node), parameters, [&values](const DataValue& v) {
    if (const auto* i = v.value.get_if<std::int32_t>()) {
      values.add(*i);
    }
  });
  EXPECT_TRUE(handle.ok()) << handle.error().describe();
  return handle.ok() ? *handle : 0;
}

bool contains(const std::vector<std::int32_t>& seen, std::int32_t value) {
  return std::find(seen.begin(), seen.end(), value) != seen.end();
}

TEST(EndToEndReconnect, LostConnectionKeepsTheSessionAndLosesNoNotification) {
  auto observed = std::make_shared<ObservedValue>(0);
  NodeId node;
  auto server = start_server(0, observed, node);
  test::TcpProxy proxy(server->port());
  SyncClient client(client_config(proxy.port()));
  Collector<ClientState> states;
  client.set_on_state([&](ClientState state, const Status&) { states.add(state); });
  ASSERT_TRUE(client.connect().ok());
  Collector<std::int32_t> values;
  SyncClient::SubscriptionId subscription = 0;
  subscribe(client, node, values, subscription);
  observed->set(1);
  ASSERT_TRUE(values.wait_until([](const auto& seen) { return contains(seen, 1); }));

  proxy.cut_and_refuse();
  ASSERT_TRUE(states.wait_until([](const auto& seen) { return seen.back() == ClientState::Reconnecting; }));
  // Values change while the client is away; the server samples each into the item's queue.
  for (std::int32_t k = 2; k <= 11; ++k) {
    observed->set(k);
    ASSERT_TRUE(observed->wait_sampled());
  }
  proxy.accept_again();
  ASSERT_TRUE(values.wait_until([](const auto& seen) { return contains(seen, 11); }, 30s));
  observed->set(12);
  ASSERT_TRUE(values.wait_until([](const auto& seen) { return contains(seen, 12); }));

  // Every value once, in order: the initial 0, then 1..12.
  std::vector<std::int32_t> expected{0};
  for (std::int32_t k = 1; k <= 12; ++k) {
    expected.push_back(k);
  }
  EXPECT_EQ(values.values(), expected);
  // The session was re-activated on the new channel, not replaced.
  EXPECT_EQ(server->session_count(), 1U);
  EXPECT_EQ(client.state(), ClientState::Connected);
  client.disconnect();
}

TEST(EndToEndReconnect, RestartedServerGetsSessionSubscriptionAndItemBack) {
  auto observed = std::make_shared<ObservedValue>(1);
  NodeId node;
  auto server = start_server(0, observed, node);
  const std::uint16_t port = server->port();
  SyncClient client(client_config(port));
  Collector<ClientState> states;
  client.set_on_state([&](ClientState state, const Status&) { states.add(state); });
  ASSERT_TRUE(client.connect().ok());
  Collector<std::int32_t> values;
  SyncClient::SubscriptionId subscription = 0;
  const std::uint32_t handle = subscribe(client, node, values, subscription);
  ASSERT_TRUE(values.wait_until([](const auto& seen) { return contains(seen, 1); }));

  server->stop();
  server.reset();
  ASSERT_TRUE(states.wait_until([](const auto& seen) { return seen.back() == ClientState::Reconnecting; }));
  auto restarted = std::make_shared<ObservedValue>(100);
  server = start_server(port, restarted, node);
  ASSERT_EQ(server->port(), port);

  // The re-created item reports the new server's current value, then its changes.
  ASSERT_TRUE(values.wait_until([](const auto& seen) { return contains(seen, 100); }, 30s));
  restarted->set(101);
  ASSERT_TRUE(values.wait_until([](const auto& seen) { return contains(seen, 101); }));
  EXPECT_EQ(client.state(), ClientState::Connected);
  EXPECT_EQ(server->session_count(), 1U);
  EXPECT_EQ(server->monitored_item_count(), 1U);
  // The handles from before the restart still name the subscription and the item.
  EXPECT_TRUE(client.unmonitor(subscription, handle).ok());
  EXPECT_TRUE(client.delete_subscription(subscription).ok());
  EXPECT_EQ(server->monitored_item_count(), 0U);
  client.disconnect();
}

}  // namespace
}  // namespace sf::opcua
