// Servers found through FindServers (OPC 10000-4 §5.4.2): which answers become server entries and
// how they are named, and the gateway collecting from a server it was not told about.
#include <gtest/gtest.h>

#include "counter_server.hpp"
#include "server_discovery.hpp"
#include "sf/cloud/gateway.hpp"

namespace sf::cloud {
namespace {

namespace ua = sf::opcua;
using test::Counter;
using test::CounterServer;
using test::eventually;
using test::TempDir;

ua::ApplicationDescription app(std::string uri, ua::ApplicationType type, std::vector<std::string> urls) {
  ua::ApplicationDescription d;
  d.application_uri = ua::String(std::move(uri));
  d.application_type = type;
  for (auto& url : urls) {
    d.discovery_urls.push_back(ua::String(std::move(url)));
  }
  return d;
}

DiscoveryConfig discovery_defaults() {
  DiscoveryConfig discovery;
  discovery.url = "opc.tcp://lds:4840";
  discovery.defaults.publishing_interval_ms = 250;
  discovery.defaults.subscribe.push_back(test::path_rule("/Objects/Line", 1));
  return discovery;
}

TEST(ServersFound, ServersBecomeEntriesNamedByApplicationUri) {
  const auto discovery = discovery_defaults();
  std::set<std::string> urls{"opc.tcp://cell-1:4840"};
  std::set<std::string> names{"cell-1"};
  const std::vector<ua::ApplicationDescription> found{
      app("urn:lds", ua::ApplicationType::DiscoveryServer, {"opc.tcp://lds:4840"}),
      app("urn:cell-1", ua::ApplicationType::Server, {"opc.tcp://cell-1:4840"}),  // configured already
      app("urn:robot/7", ua::ApplicationType::Server, {"http://robot:80", "opc.tcp://robot:4840/ua"}),
      app("urn:host:smartfactory", ua::ApplicationType::Server, {"opc.tcp://host:4841"}),
      app("urn:host:smartfactory", ua::ApplicationType::ClientAndServer, {"opc.tcp://host:4842"}),
      app("urn:no-url", ua::ApplicationType::Server, {}),
      app("urn:client", ua::ApplicationType::Client, {"opc.tcp://client:4840"}),
  };
  const auto added = detail::servers_found(found, discovery, urls, names);
  ASSERT_EQ(added.size(), 3U);
  EXPECT_EQ(added[0].name, "urn:robot_7");  // no '/' in a folder name
  EXPECT_EQ(added[0].url, "opc.tcp://robot:4840/ua");
  EXPECT_EQ(added[0].publishing_interval_ms, 250);
  ASSERT_EQ(added[0].subscribe.size(), 1U);
  EXPECT_EQ(added[0].subscribe[0].browse_path, "/Objects/Line");
  EXPECT_EQ(added[1].name, "urn:host:smartfactory");
  EXPECT_EQ(added[2].name, "urn:host:smartfactory@host:4842");  // servers sharing a certificate
  // Asked again, nothing is new.
  EXPECT_TRUE(detail::servers_found(found, discovery, urls, names).empty());
}

TEST(GatewayDiscovery, AServerFoundWithFindServersIsCollectedLikeAConfiguredOne) {
  TempDir dir;
  auto listed = std::make_shared<Counter>();
  auto found = std::make_shared<Counter>();
  CounterServer configured(0, {listed});
  CounterServer discovered(0, {found});
  ASSERT_TRUE(configured.ok() && discovered.ok());
  GatewayConfig config;
  config.historian.url = "sqlite:" + (dir.path() / "h.db").string();
  config.historian.buffer = dir.path() / "buffer";
  config.historian.flush_interval = std::chrono::milliseconds(20);
  config.servers.push_back(test::server_config("line",
                                               "opc.tcp://127.0.0.1:" + std::to_string(configured.port()),
                                               {test::path_rule("/Objects/Line", 1)}));
  DiscoveryConfig discovery = discovery_defaults();
  discovery.url = "opc.tcp://127.0.0.1:" + std::to_string(discovered.port());
  discovery.defaults.sampling_interval_ms = 10;
  config.discovery = discovery;
  auto gateway = Gateway::create(config);
  ASSERT_TRUE(gateway.ok()) << gateway.error().message;
  ASSERT_TRUE((*gateway)->start().ok());
  ASSERT_TRUE(eventually([&] {
    const auto s = (*gateway)->status();
    return s.servers.size() == 2 && s.servers[0].phase == "subscribed" && s.servers[1].phase == "subscribed";
  }));
  const auto status = (*gateway)->status();
  ASSERT_TRUE(status.discovery.has_value());
  EXPECT_EQ(status.discovery->found, 1U);
  EXPECT_EQ(status.servers[1].url, discovery.url);
  found->set(42);
  ASSERT_TRUE(eventually([&] { return (*gateway)->status().samples_written >= 3; }));
  (*gateway)->stop();
  auto series = (*gateway)->store().list_series();
  ASSERT_TRUE(series.ok());
  ASSERT_EQ(series->size(), 2U);
  const auto it = std::find_if(series->begin(), series->end(), [&](const historian::Series& s) {
    return s.info.server == status.servers[1].name;
  });
  ASSERT_NE(it, series->end());
  auto samples = (*gateway)->store().read_raw(it->id, historian::from_micros(0),
                                              historian::from_micros(INT64_MAX / 2), 100);
  ASSERT_TRUE(samples.ok());
  ASSERT_FALSE(samples->empty());
  EXPECT_EQ(std::get<std::int64_t>(samples->back().value), 42);
}

TEST(GatewayDiscovery, AnUnreachableDiscoveryUrlIsReportedAndConfiguredServersWork) {
  TempDir dir;
  auto counter = std::make_shared<Counter>();
  CounterServer server(0, {counter});
  ASSERT_TRUE(server.ok());
  GatewayConfig config;
  config.historian.url = "sqlite:" + (dir.path() / "h.db").string();
  config.historian.buffer = dir.path() / "buffer";
  config.servers.push_back(test::server_config("line", "opc.tcp://127.0.0.1:" + std::to_string(server.port()),
                                               {test::path_rule("/Objects/Line", 1)}));
  DiscoveryConfig discovery = discovery_defaults();
  discovery.url = "opc.tcp://127.0.0.1:1";
  config.discovery = discovery;
  auto gateway = Gateway::create(config);
  ASSERT_TRUE(gateway.ok());
  ASSERT_TRUE((*gateway)->start().ok());
  ASSERT_TRUE(eventually([&] {
    const auto s = (*gateway)->status();
    return s.discovery && !s.discovery->last_error.empty() && s.servers.size() == 1 &&
           s.servers[0].phase == "subscribed";
  }));
  (*gateway)->stop();
}

}  // namespace
}  // namespace sf::cloud
