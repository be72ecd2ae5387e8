// Reading cloud.yaml (see config.hpp). Every key is checked: a misspelt key is an error, not a
// silently ignored setting.
#include "sf/cloud/config.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <set>

#include "sf/core/config.hpp"

namespace sf::cloud {

namespace {

using config::Node;

Result<SubscribeRule> parse_rule(const Node& node) {
  SF_TRY(node.only_keys({"browse_path", "node", "type", "depth"}));
  SubscribeRule rule;
  SF_TRY(node.read("browse_path", rule.browse_path));
  SF_TRY(node.read("node", rule.node));
  SF_TRY(node.read("type", rule.type));
  SF_TRY(node.read("depth", rule.depth));
  const int kinds = int{!rule.browse_path.empty()} + int{!rule.node.empty()} + int{!rule.type.empty()};
  if (kinds != 1) {
    return node.error("a subscribe rule names exactly one of browse_path, node and type");
  }
  if (!rule.browse_path.empty() && rule.browse_path.front() != '/') {
    return node.error(fmt::format("browse_path '{}' must start at the Root with '/'", rule.browse_path));
  }
  if (rule.depth > 16) {
    return node.error("depth is at most 16");
  }
  return rule;
}

// How to connect (OPC 10000-4 §5.6.3, §7.41): security POLICY:MODE, none or auto; a user name with a password
// file, or a user certificate and key. Checked further by the application that applies it.
Status parse_connection_security(const Node& node, ConnectionSecurity& out) {
  SF_TRY(node.read("security", out.security));
  SF_TRY(node.read("user", out.user));
  SF_TRY(node.read("password_file", out.password_file));
  SF_TRY(node.read("user_certificate", out.user_certificate));
  SF_TRY(node.read("user_key", out.user_key));
  if (!out.password_file.empty() && out.user.empty()) {
    return node.error("password_file needs a user");
  }
  if (!out.user.empty() && out.password_file.empty()) {
    return node.error("user needs a password_file (the gateway runs unattended)");
  }
  if (out.user_certificate.empty() != out.user_key.empty()) {
    return node.error("user_certificate and user_key go together");
  }
  return {};
}

// The settings a server entry and the discovery defaults share.
Status parse_subscription_settings(const Node& node, ServerConfig& out) {
  SF_TRY(node.read("publishing_interval_ms", out.publishing_interval_ms));
  SF_TRY(node.read("sampling_interval_ms", out.sampling_interval_ms));
  SF_TRY(node.read("queue_size", out.queue_size));
  SF_TRY(node.read("events", out.events));
  auto rediscover = out.rediscover.count();
  SF_TRY(node.read("rediscover_s", rediscover));
  out.rediscover = std::chrono::seconds(rediscover);
  if (out.publishing_interval_ms <= 0 || out.sampling_interval_ms < 0 || out.queue_size == 0 ||
      rediscover < 0) {
    return node.error(
        "publishing_interval_ms > 0, sampling_interval_ms >= 0, queue_size > 0 and rediscover_s >= 0 are "
        "needed");
  }
  SF_TRY(parse_connection_security(node, out.security));
  if (node.has("subscribe")) {
    auto list = node.child("subscribe");
    if (!list) {
      return list.error();
    }
    auto items = list->items();
    if (!items) {
      return items.error();
    }
    for (const Node& item : *items) {
      auto rule = parse_rule(item);
      if (!rule) {
        return rule.error();
      }
      out.subscribe.push_back(std::move(*rule));
    }
  }
  if (out.subscribe.empty() && !out.events) {
    return node.error("nothing to collect: give subscribe rules or events: true");
  }
  return {};
}

Status check_url(const Node& node, const std::string& url) {
  if (!url.starts_with("opc.tcp://") || url.size() <= 10) {
    return node.error(fmt::format("'{}' is not an opc.tcp:// URL", url));
  }
  return {};
}

Result<ServerConfig> parse_server(const Node& node) {
  SF_TRY(node.only_keys({"name", "url", "publishing_interval_ms", "sampling_interval_ms", "queue_size",
                         "events", "rediscover_s", "subscribe", "security", "user", "password_file",
                         "user_certificate", "user_key"}));
  ServerConfig server;
  auto name = node.get<std::string>("name");
  auto url = node.get<std::string>("url");
  if (!name) {
    return name.error();
  }
  if (!url) {
    return url.error();
  }
  server.name = *name;
  server.url = *url;
  if (server.name.empty() || server.name.find('/') != std::string::npos) {
    return node.error("a server needs a name without '/'");
  }
  SF_TRY(check_url(*node.child("url"), server.url));
  SF_TRY(parse_subscription_settings(node, server));
  return server;
}

Status parse_historian(const Node& node, HistorianConfig& out) {
  SF_TRY(node.only_keys({"url", "buffer", "batch", "flush_ms"}));
  SF_TRY(node.read("url", out.url));
  std::string buffer = out.buffer.string();
  SF_TRY(node.read("buffer", buffer));
  out.buffer = buffer;
  SF_TRY(node.read("batch", out.batch));
  auto flush = out.flush_interval.count();
  SF_TRY(node.read("flush_ms", flush));
  out.flush_interval = std::chrono::milliseconds(flush);
  if (!out.url.starts_with("sqlite:") && !out.url.starts_with("postgresql://") &&
      !out.url.starts_with("postgres://")) {
    return node.error(fmt::format("historian url '{}' is neither sqlite:PATH nor postgresql://...", out.url));
  }
  if (out.batch == 0 || flush <= 0) {
    return node.error("batch and flush_ms must be positive");
  }
  return {};
}

Status parse_aggregating(const Node& node, AggregatingServerConfig& out) {
  SF_TRY(node.only_keys({"host", "port", "enabled", "security", "policies", "users", "anonymous"}));
  out.enabled = true;
  SF_TRY(node.read("host", out.host));
  SF_TRY(node.read("port", out.port));
  SF_TRY(node.read("enabled", out.enabled));
  SF_TRY(node.read("security", out.security));
  SF_TRY(node.read("policies", out.policies));
  SF_TRY(node.read("users", out.users));
  SF_TRY(node.read("anonymous", out.anonymous));
  return {};
}

Result<DiscoveryConfig> parse_discovery(const Node& node) {
  SF_TRY(node.only_keys({"url", "interval_s", "publishing_interval_ms", "sampling_interval_ms", "queue_size",
                         "events", "rediscover_s", "subscribe", "security", "user", "password_file",
                         "user_certificate", "user_key"}));
  DiscoveryConfig discovery;
  auto interval = discovery.interval.count();
  SF_TRY(node.read("interval_s", interval));
  if (interval <= 0) {
    return node.error("interval_s must be positive");
  }
  discovery.interval = std::chrono::seconds(interval);
  auto url = node.get<std::string>("url");
  if (!url) {
    return url.error();
  }
  discovery.url = *url;
  SF_TRY(check_url(*node.child("url"), discovery.url));
  SF_TRY(parse_subscription_settings(node, discovery.defaults));
  return discovery;
}

Result<KnowledgeConfig> parse_knowledge(const Node& node) {
  SF_TRY(node.only_keys({"layout", "ontology", "rules", "due_after_s"}));
  KnowledgeConfig k;
  std::string layout;
  std::string ontology;
  std::string rules;
  SF_TRY(node.read("layout", layout));
  SF_TRY(node.read("ontology", ontology));
  SF_TRY(node.read("rules", rules));
  k.layout = layout;
  k.ontology = ontology;
  k.rules = rules;
  auto due = k.due_after.count();
  SF_TRY(node.read("due_after_s", due));
  if (due < 0) {
    return node.error("due_after_s must be 0 (no due times) or more");
  }
  k.due_after = std::chrono::seconds(due);
  return k;
}

Result<GatewayConfig> parse_root(const Node& root) {
  SF_TRY(root.only_keys({"historian", "servers", "discovery", "aggregating_server", "pki", "knowledge"}));
  GatewayConfig config;
  SF_TRY(root.read("pki", config.pki));
  if (root.has("knowledge")) {
    auto knowledge = parse_knowledge(*root.child("knowledge"));
    if (!knowledge) {
      return knowledge.error();
    }
    config.knowledge = std::move(*knowledge);
  }
  if (root.has("historian")) {
    SF_TRY(parse_historian(*root.child("historian"), config.historian));
  }
  if (root.has("aggregating_server")) {
    SF_TRY(parse_aggregating(*root.child("aggregating_server"), config.aggregating_server));
  }
  if (root.has("discovery")) {
    auto discovery = parse_discovery(*root.child("discovery"));
    if (!discovery) {
      return discovery.error();
    }
    config.discovery = std::move(*discovery);
  }
  std::set<std::string> names;
  auto servers =
      root.has("servers") ? root.child("servers")->items() : Result<std::vector<Node>>(std::vector<Node>{});
  if (!servers) {
    return servers.error();
  }
  for (const Node& node : *servers) {
    auto server = parse_server(node);
    if (!server) {
      return server.error();
    }
    if (!names.insert(server->name).second) {
      return node.error(fmt::format("server name '{}' is used twice", server->name));
    }
    config.servers.push_back(std::move(*server));
  }
  if (config.servers.empty() && !config.discovery) {
    return root.error("no servers: list them under servers: or give a discovery: url");
  }
  return config;
}

}  // namespace

Result<GatewayConfig> load_gateway_config(const std::filesystem::path& file) {
  auto root = config::load_file(file);
  if (!root) {
    return root.error();
  }
  return parse_root(*root);
}

Result<GatewayConfig> parse_gateway_config(std::string_view yaml, std::string name) {
  auto root = config::load_string(yaml, std::move(name));
  if (!root) {
    return root.error();
  }
  return parse_root(*root);
}

}  // namespace sf::cloud
