// HistoryRead end to end: our client reads the history our server keeps of a Historizing
// variable (MemoryHistory), page by page through continuation points.
#include <gtest/gtest.h>

#include <memory>

#include "sf/opcua/client/client.hpp"
#include "sf/opcua/server/history.hpp"
#include "sf/opcua/server/server.hpp"

namespace sf::opcua {
namespace {

DateTime at(std::int64_t seconds) {
  return DateTime::from_unix_seconds(1'700'000'000 + seconds);
}

TEST(EndToEndHistory, ClientReadsTheServersHistoryAcrossContinuationPoints) {
  server::ServerConfig config;
  config.transport.host = "127.0.0.1";
  config.transport.port = 0;
  config.advertised_host = "127.0.0.1";
  server::Server server(config);
  auto history = std::make_shared<server::MemoryHistory>();
  NodeId node;
  NodeId plain;
  server.with_address_space([&](server::AddressSpace& space) {
    const std::uint16_t ns = space.add_namespace("urn:smartfactory:test:history");
    server::VariableSpec spec;
    spec.browse_name = QualifiedName(ns, "Level");
    spec.parent = NodeId(0, id::ObjectsFolder);
    spec.reference_type = NodeId(0, id::Organizes);
    spec.data_type = NodeId(0, id::Double);
    spec.historizing = true;
    spec.access_level = server::access_level::CurrentRead | server::access_level::HistoryRead;
    spec.user_access_level = spec.access_level;
    node = *space.add_variable(spec);
    spec.browse_name = QualifiedName(ns, "Plain");
    spec.historizing = false;
    spec.access_level = server::access_level::CurrentRead;
    plain = *space.add_variable(spec);
    history->attach(space);
    for (int i = 0; i < 25; ++i) {
      DataValue value{Variant(i * 0.5)};
      value.source_timestamp = at(i);
      ASSERT_TRUE(space.set_value(node, value));
    }
  });
  server.set_history_database(history);
  ASSERT_TRUE(server.start().ok());

  ClientConfig client_config;
  client_config.endpoint_url = "opc.tcp://127.0.0.1:" + std::to_string(server.port());
  SyncClient client(client_config);
  ASSERT_TRUE(client.connect().ok());
  // Seconds 3..19, four values per response: five requests.
  auto values = client.history_read_raw(node, {.start = at(3), .end = at(20), .max_values = 4});
  ASSERT_TRUE(values.ok()) << values.error().describe();
  ASSERT_EQ(values->size(), 17U);
  for (std::size_t i = 0; i < values->size(); ++i) {
    EXPECT_EQ((*values)[i].value, Variant((static_cast<double>(i) + 3) * 0.5));
    EXPECT_EQ((*values)[i].source_timestamp, at(static_cast<std::int64_t>(i) + 3));
  }
  // The newest three, backwards from the end.
  auto last = client.history_read_raw(node, {.start = DateTime::min(), .end = at(100), .max_values = 3});
  ASSERT_TRUE(last.ok());
  ASSERT_EQ(last->size(), 3U);
  EXPECT_EQ(last->front().value, Variant(12.0));
  // A variable without history access.
  auto refused = client.history_read_raw(plain, {.start = at(0), .end = at(10), .max_values = 0});
  ASSERT_FALSE(refused.ok());
  EXPECT_EQ(status_of(refused.error()), StatusCode(status::BadNotReadable));
  client.disconnect();
  server.stop();
  history->detach();
}

}  // namespace
}  // namespace sf::opcua
