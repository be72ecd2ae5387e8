// cloud.yaml: a complete file reads into the settings, and each kind of mistake is refused with
// file:line:column and the key path.
#include "sf/cloud/config.hpp"

#include <gtest/gtest.h>

namespace sf::cloud {
namespace {

constexpr std::string_view kFull = R"(historian:
  url: postgresql://sf@db:5432/plant
  buffer: /var/lib/sf/buffer
  batch: 500
  flush_ms: 50
servers:
  - name: line-1
    url: opc.tcp://10.0.0.5:4840
    publishing_interval_ms: 250
    sampling_interval_ms: 0
    queue_size: 4
    events: true
    rediscover_s: 0
    subscribe:
      - browse_path: /Objects/Demo
        depth: 2
      - node: nsu=urn:smartfactory:demo;s=Demo.Counter
    security: Aes256_Sha256_RsaPss:Sign
    user: gateway
    password_file: /etc/sf/gateway.pw
  - name: line-2
    url: opc.tcp://10.0.0.6:4840
    subscribe:
      - type: nsu=urn:example;i=1000
discovery:
  url: opc.tcp://lds:4840
  interval_s: 5
  security: none
  subscribe: [{browse_path: /Objects}]
aggregating_server:
  port: 4850
  security: encrypt
  users: /etc/sf/users.yaml
  anonymous: "off"
pki: /var/lib/sf/pki
knowledge:
  layout: /etc/sf/line.yaml
  rules: /etc/sf/line.rules
  due_after_s: 900
)";

TEST(GatewayConfig, ReadsEverySetting) {
  auto config = parse_gateway_config(kFull, "cloud.yaml");
  ASSERT_TRUE(config.ok()) << config.error().message;
  EXPECT_EQ(config->historian.url, "postgresql://sf@db:5432/plant");
  EXPECT_EQ(config->historian.buffer, "/var/lib/sf/buffer");
  EXPECT_EQ(config->historian.batch, 500U);
  EXPECT_EQ(config->historian.flush_interval.count(), 50);
  ASSERT_EQ(config->servers.size(), 2U);
  const ServerConfig& line1 = config->servers[0];
  EXPECT_EQ(line1.name, "line-1");
  EXPECT_EQ(line1.publishing_interval_ms, 250.0);
  EXPECT_EQ(line1.sampling_interval_ms, 0.0);
  EXPECT_EQ(line1.queue_size, 4U);
  EXPECT_TRUE(line1.events);
  EXPECT_EQ(line1.rediscover.count(), 0) << "0: the rules are matched when connecting only";
  ASSERT_EQ(line1.subscribe.size(), 2U);
  EXPECT_EQ(line1.subscribe[0].browse_path, "/Objects/Demo");
  EXPECT_EQ(line1.subscribe[0].depth, 2U);
  EXPECT_EQ(line1.subscribe[1].node, "nsu=urn:smartfactory:demo;s=Demo.Counter");
  EXPECT_EQ(config->servers[1].subscribe[0].type, "nsu=urn:example;i=1000");
  EXPECT_EQ(config->servers[1].publishing_interval_ms, 100.0);  // default
  EXPECT_EQ(config->servers[1].rediscover.count(), 10);         // default
  EXPECT_EQ(line1.security.security, "Aes256_Sha256_RsaPss:Sign");
  EXPECT_EQ(line1.security.user, "gateway");
  EXPECT_EQ(line1.security.password_file, "/etc/sf/gateway.pw");
  EXPECT_EQ(config->servers[1].security.security, "auto");  // secure by default
  ASSERT_TRUE(config->discovery.has_value());
  EXPECT_EQ(config->discovery->url, "opc.tcp://lds:4840");
  EXPECT_EQ(config->discovery->defaults.subscribe[0].browse_path, "/Objects");
  EXPECT_EQ(config->discovery->interval.count(), 5);
  EXPECT_EQ(config->discovery->defaults.security.security, "none");
  EXPECT_TRUE(config->aggregating_server.enabled);
  EXPECT_EQ(config->aggregating_server.port, 4850);
  EXPECT_EQ(config->aggregating_server.security, "encrypt");
  EXPECT_EQ(config->aggregating_server.users, "/etc/sf/users.yaml");
  EXPECT_EQ(config->aggregating_server.anonymous, "off");
  EXPECT_EQ(config->pki, "/var/lib/sf/pki");
  ASSERT_TRUE(config->knowledge.has_value());
  EXPECT_EQ(config->knowledge->layout, "/etc/sf/line.yaml");
  EXPECT_EQ(config->knowledge->rules, "/etc/sf/line.rules");
  EXPECT_TRUE(config->knowledge->ontology.empty());  // the built-in one
  EXPECT_EQ(config->knowledge->due_after.count(), 900);
}

TEST(GatewayConfig, KnowledgeIsOnWhenItsSectionIsThere) {
  const std::string servers = "servers: [{name: a, url: 'opc.tcp://x:1', subscribe: [{node: i=85}]}]\n";
  auto off = parse_gateway_config(servers);
  ASSERT_TRUE(off) << off.error().message;
  EXPECT_FALSE(off->knowledge.has_value());
  auto on = parse_gateway_config(servers + "knowledge: {}\n");
  ASSERT_TRUE(on) << on.error().message;
  ASSERT_TRUE(on->knowledge.has_value());
  EXPECT_EQ(on->knowledge->due_after.count(), 0);
}

struct Bad {
  std::string yaml;
  std::string expected;  // in the message, with the location
};

TEST(GatewayConfig, MistakesNameTheirPlace) {
  const std::vector<Bad> cases = {
      {"servers:\n  - name: a\n    url: http://x\n    subscribe: [{node: i=85}]\n", "c.yaml:3:10"},
      {"servers:\n  - name: a\n    url: opc.tcp://x:4840\n    subscribe: [{node: i=85}]\n    sampling: 5\n",
       "unknown setting 'sampling'"},
      {"servers:\n  - name: a\n    url: opc.tcp://x:4840\n", "nothing to collect"},
      {"servers:\n  - {name: a, url: 'opc.tcp://x:1', subscribe: [{node: i=85}], user: u}\n",
       "password_file"},
      {"discovery: {url: 'opc.tcp://x:1', interval_s: 0, subscribe: [{node: i=85}]}\n", "interval_s"},
      {"servers:\n  - url: opc.tcp://x:4840\n    subscribe: [{node: i=85}]\n", "name"},
      {"servers:\n  - name: a\n    url: opc.tcp://x:4840\n    subscribe: [{node: i=85, type: i=58}]\n",
       "exactly one of"},
      {"servers:\n  - name: a\n    url: opc.tcp://x:4840\n    subscribe: [{browse_path: Objects}]\n",
       "must start at the Root"},
      {"servers:\n  - {name: a, url: 'opc.tcp://x:1', subscribe: [{node: i=85}]}\n"
       "  - {name: a, url: 'opc.tcp://y:1', subscribe: [{node: i=85}]}\n",
       "c.yaml:3:5: servers[1]: server name 'a' is used twice"},
      {"historian: {url: mysql://x}\nservers: [{name: a, url: 'opc.tcp://x:1', subscribe: [{node: i=85}]}]\n",
       "neither sqlite:PATH nor postgresql://"},
      {"servers:\n  - name: a\n    url: opc.tcp://x:4840\n    queue_size: lots\n    subscribe: [{node: "
       "i=85}]\n",
       "c.yaml:4:17"},
      {"historian: {url: 'sqlite:x.db'}\n", "no servers"},
      {"servers: [{name: a, url: 'opc.tcp://x:1', rediscover_s: -5, subscribe: [{node: i=85}]}]\n",
       "rediscover_s >= 0"},
      {"servers: [\n", "c.yaml:"},
      {"servers: [{name: a, url: 'opc.tcp://x:1', subscribe: [{node: i=85}]}]\nknowledge: {due_after_s: "
       "-1}\n",
       "due_after_s"},
      {"servers: [{name: a, url: 'opc.tcp://x:1', subscribe: [{node: i=85}]}]\nknowledge: {rule: x}\n",
       "unknown setting 'rule'"},
  };
  for (const Bad& bad : cases) {
    auto config = parse_gateway_config(bad.yaml, "c.yaml");
    ASSERT_FALSE(config.ok()) << bad.yaml;
    EXPECT_NE(config.error().message.find(bad.expected), std::string::npos)
        << "expected '" << bad.expected << "' in: " << config.error().message;
  }
}

TEST(GatewayConfig, MissingFileIsAClearError) {
  auto config = load_gateway_config("/nonexistent/cloud.yaml");
  ASSERT_FALSE(config.ok());
  EXPECT_NE(config.error().message.find("/nonexistent/cloud.yaml"), std::string::npos);
}

}  // namespace
}  // namespace sf::cloud
