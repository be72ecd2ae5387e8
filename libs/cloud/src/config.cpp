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

Status only_keys(const Node& node, std::initializer_list<std::string_view> allowed) {
  auto keys = node.keys();
  if (!keys) {
    return keys.error();
  }
  for (const std::string& key : *keys) {
    if (std::find(allowed.begin(), allowed.end(), key) == allowed.end()) {
      std::string list;
      for (std::string_view a : allowed) {
        list += (list.empty() ? "" : ", ") + std::string(a);
      }
      auto child = node.child(key);
      return (child ? *child : node).error(fmt::format("unknown setting '{}' (known: {})", key, list));
    }
  }
  return {};
}

Result<SubscribeRule> parse_rule(const Node& node) {
  SF_TRY(only_keys(node, {"browse_path", "node", "type", "depth"}));
  SubscribeRule rule;
  auto browse_path = node.get_or<std::string>("browse_path", "");
  auto id = node.get_or<std::string>("node", "");
  auto type = node.get_or<std::string>("type", "");
  auto depth = node.get_or<unsigned>("depth", 3);
  for (const auto* r : {&browse_path, &id, &type}) {
    if (!*r) {
      return r->error();
    }
  }
  if (!depth) {
    return depth.error();
  }
  rule.browse_path = *browse_path;
  rule.node = *id;
  rule.type = *type;
  rule.depth = *depth;
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

// The settings a server entry and the discovery defaults share.
Status parse_subscription_settings(const Node& node, ServerConfig& out) {
  auto publishing = node.get_or<double>("publishing_interval_ms", out.publishing_interval_ms);
  auto sampling = node.get_or<double>("sampling_interval_ms", out.sampling_interval_ms);
  auto queue = node.get_or<std::uint32_t>("queue_size", out.queue_size);
  auto events = node.get_or<bool>("events", out.events);
  if (!publishing || !sampling || !queue || !events) {
    return !publishing ? publishing.error()
                       : (!sampling ? sampling.error() : (!queue ? queue.error() : events.error()));
  }
  if (*publishing <= 0 || *sampling < 0 || *queue == 0) {
    return node.error("publishing_interval_ms > 0, sampling_interval_ms >= 0 and queue_size > 0 are needed");
  }
  out.publishing_interval_ms = *publishing;
  out.sampling_interval_ms = *sampling;
  out.queue_size = *queue;
  out.events = *events;
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
  SF_TRY(only_keys(node, {"name", "url", "publishing_interval_ms", "sampling_interval_ms", "queue_size",
                          "events", "subscribe"}));
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
  SF_TRY(only_keys(node, {"url", "buffer", "batch", "flush_ms"}));
  auto url = node.get_or<std::string>("url", out.url);
  auto buffer = node.get_or<std::string>("buffer", out.buffer.string());
  auto batch = node.get_or<std::size_t>("batch", out.batch);
  auto flush = node.get_or<std::int64_t>("flush_ms", out.flush_interval.count());
  if (!url || !buffer || !batch || !flush) {
    return !url ? url.error() : (!buffer ? buffer.error() : (!batch ? batch.error() : flush.error()));
  }
  if (!url->starts_with("sqlite:") && !url->starts_with("postgresql://") &&
      !url->starts_with("postgres://")) {
    return node.error(fmt::format("historian url '{}' is neither sqlite:PATH nor postgresql://...", *url));
  }
  if (*batch == 0 || *flush <= 0) {
    return node.error("batch and flush_ms must be positive");
  }
  out.url = *url;
  out.buffer = *buffer;
  out.batch = *batch;
  out.flush_interval = std::chrono::milliseconds(*flush);
  return {};
}

Status parse_aggregating(const Node& node, AggregatingServerConfig& out) {
  SF_TRY(only_keys(node, {"host", "port", "enabled"}));
  auto host = node.get_or<std::string>("host", out.host);
  auto port = node.get_or<std::uint16_t>("port", out.port);
  auto enabled = node.get_or<bool>("enabled", true);
  if (!host || !port || !enabled) {
    return !host ? host.error() : (!port ? port.error() : enabled.error());
  }
  out.host = *host;
  out.port = *port;
  out.enabled = *enabled;
  return {};
}

Result<DiscoveryConfig> parse_discovery(const Node& node) {
  SF_TRY(only_keys(
      node, {"url", "publishing_interval_ms", "sampling_interval_ms", "queue_size", "events", "subscribe"}));
  DiscoveryConfig discovery;
  auto url = node.get<std::string>("url");
  if (!url) {
    return url.error();
  }
  discovery.url = *url;
  SF_TRY(check_url(*node.child("url"), discovery.url));
  SF_TRY(parse_subscription_settings(node, discovery.defaults));
  return discovery;
}

Result<GatewayConfig> parse_root(const Node& root) {
  SF_TRY(only_keys(root, {"historian", "servers", "discovery", "aggregating_server"}));
  GatewayConfig config;
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
