#include "sf/cloud/gateway.hpp"

#include <fmt/format.h>

#include <atomic>
#include <mutex>

#include "aggregating_server.hpp"
#include "knowledge_defaults.hpp"
#include "sample_writer.hpp"
#include "server_discovery.hpp"
#include "server_link.hpp"
#include "sf/core/config.hpp"
#include "sf/core/log.hpp"
#include "sf/line/layout.hpp"

namespace sf::cloud {

struct Gateway::Impl {
  GatewayConfig config;
  GatewayOptions options;
  LiveBus bus;
  std::unique_ptr<historian::BufferedStore> store;
  std::unique_ptr<detail::SampleWriter> writer;
  std::unique_ptr<detail::AggregatingServer> aggregating;
  // The aggregating server while it runs: the alarms' events go there too (any thread).
  std::atomic<detail::AggregatingServer*> alarm_events{nullptr};
  std::unique_ptr<KnowledgeLoop> knowledge;
  LiveBus::Subscription to_knowledge;
  LiveBus::Subscription to_aggregating;
  std::function<void(const historian::Series&)> on_series;
  std::unique_ptr<detail::ServerDiscovery> discovery;
  mutable std::mutex links_mutex;  // discovery adds links while status() reads them
  std::vector<std::unique_ptr<detail::ServerLink>> links;
  bool started = false;

  Status start_aggregating();
  // A link for `server` with the client settings the hook made; not started.
  Result<std::unique_ptr<detail::ServerLink>> make_link(const ServerConfig& server);
  void add_discovered(const ServerConfig& server);
  Status start_knowledge(const KnowledgeConfig& k);
};

namespace {

Result<std::string> file_or(const std::filesystem::path& file, std::string_view built_in,
                            std::string_view what) {
  if (file.empty()) {
    return std::string(built_in);
  }
  auto text = config::read_text(file);
  if (!text) {
    return text.error().with_context(fmt::format("knowledge {}", what));
  }
  return std::move(*text);
}

}  // namespace

// Alarms go to the historian as events of the server "knowledge" (through the writer, as the
// servers' events do), to the live bus (applications follow them as they follow servers'
// events), to the aggregating server's subscribers as condition events, and to the log.
Status Gateway::Impl::start_knowledge(const KnowledgeConfig& k) {
  auto layout = k.layout.empty() ? line::default_layout() : line::load_layout(k.layout);
  if (!layout) {
    return layout.error().with_context("knowledge layout");
  }
  KnowledgeLoopOptions o;
  auto ontology = file_or(k.ontology, detail::default_ontology(), "ontology");
  auto rules = file_or(k.rules, detail::default_rules(), "rules");
  if (!ontology || !rules) {
    return !ontology ? ontology.error() : rules.error();
  }
  o.ontology = std::move(*ontology);
  o.rules = std::move(*rules);
  o.rules_name = k.rules.empty() ? "rules/candy-factory.rules" : k.rules.string();
  o.due_after = k.due_after;
  o.clock = options.clock;
  auto loop = KnowledgeLoop::create(*layout, o, [this](const Alarm& a) {
    log::get("knowledge")
        ->warn("alarm {} {}: {} (rule {})", to_string(a.change), a.entity, a.message, a.rule);
    auto event = alarm_event(a, kKnowledgeServer);
    bus.publish(event);
    writer->push(std::move(event));
    if (auto* server = alarm_events.load()) {
      server->report(a);
    }
  });
  if (!loop) {
    return loop.error().with_context("knowledge");
  }
  knowledge = std::move(*loop);
  to_knowledge = bus.subscribe([k = knowledge.get()](const LiveUpdate& u) { k->on_value(u); });
  return {};
}

Result<std::unique_ptr<Gateway>> Gateway::create(GatewayConfig config, GatewayOptions options) {
  auto impl = std::make_unique<Impl>();
  historian::BufferOptions buffer;
  buffer.directory = config.historian.buffer;
  auto store = historian::BufferedStore::open(config.historian.url, buffer, *options.clock);
  if (!store) {
    return store.error().with_context(fmt::format("historian {}", config.historian.url));
  }
  impl->store = std::move(*store);
  impl->writer = std::make_unique<detail::SampleWriter>(*impl->store, config.historian.batch,
                                                        config.historian.flush_interval, options.on_commit);
  impl->config = std::move(config);
  impl->options = std::move(options);
  if (impl->config.knowledge) {
    SF_TRY(impl->start_knowledge(*impl->config.knowledge));
  }
  return std::unique_ptr<Gateway>(new Gateway(std::move(impl)));
}

Gateway::Gateway(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}

Gateway::~Gateway() {
  stop();
}

Status Gateway::Impl::start_aggregating() {
  auto server_config = detail::AggregatingServer::server_config(config.aggregating_server);
  if (options.configure_aggregating_server) {
    SF_TRY(options.configure_aggregating_server(config.aggregating_server, server_config));
  }
  aggregating = std::make_unique<detail::AggregatingServer>(server_config, *store);
  if (auto st = aggregating->start(); !st) {
    aggregating.reset();
    return st;
  }
  to_aggregating = bus.subscribe([server = aggregating.get()](const LiveUpdate& u) {
    if (!u.replayed) {  // its current values only move forward
      server->update(u);
    }
  });
  on_series = [server = aggregating.get()](const historian::Series& s) { server->add_series(s); };
  alarm_events = aggregating.get();
  if (knowledge) {
    aggregating->refresh_from([k = knowledge.get()] { return k->retained_alarms(); });
  }
  // Series known from earlier runs have history already: show them from the start.
  if (auto known = store->list_series()) {
    for (const historian::Series& s : *known) {
      aggregating->add_series(s);
    }
  }
  return {};
}

Result<std::unique_ptr<detail::ServerLink>> Gateway::Impl::make_link(const ServerConfig& server) {
  auto client = detail::ServerLink::client_config(server);
  if (options.configure_client) {
    if (auto st = options.configure_client(server, client); !st) {
      return st.error().with_context(fmt::format("server {}", server.name));
    }
  }
  return std::make_unique<detail::ServerLink>(server, std::move(client), *store, *writer, bus, on_series,
                                              *options.clock);
}

void Gateway::Impl::add_discovered(const ServerConfig& server) {
  auto link = make_link(server);
  if (!link) {
    log::get("cloud")->error("{}", link.error().message);
    return;
  }
  std::lock_guard lock(links_mutex);
  if (!started) {
    return;
  }
  links.push_back(std::move(*link));
  links.back()->start();
}

Status Gateway::start() {
  Impl& g = *impl_;
  if (g.started) {
    return {};
  }
  if (g.config.aggregating_server.enabled) {
    if (auto st = g.start_aggregating(); !st) {
      return st.error().with_context("aggregating server");
    }
  }
  std::vector<std::unique_ptr<detail::ServerLink>> links;
  for (const ServerConfig& server : g.config.servers) {
    auto link = g.make_link(server);
    if (!link) {
      return link.error();
    }
    links.push_back(std::move(*link));
  }
  {
    std::lock_guard lock(g.links_mutex);
    g.links = std::move(links);
    for (auto& link : g.links) {
      link->start();
    }
    g.started = true;
  }
  if (g.config.discovery) {
    std::set<std::string> urls;
    std::set<std::string> names;
    for (const ServerConfig& server : g.config.servers) {
      urls.insert(server.url);
      names.insert(server.name);
    }
    g.discovery = std::make_unique<detail::ServerDiscovery>(
        *g.config.discovery, std::move(urls), std::move(names),
        [&g](const ServerConfig& server) { g.add_discovered(server); });
    g.discovery->start();
  }
  log::get("cloud")->info(
      "gateway started: {} servers{}, historian {}{}", g.config.servers.size(),
      g.discovery ? fmt::format(" + discovery at {}", g.config.discovery->url) : "", g.config.historian.url,
      g.aggregating ? fmt::format(", aggregating server on port {}", g.aggregating->port()) : "");
  return {};
}

void Gateway::stop() {
  Impl& g = *impl_;
  if (g.discovery) {
    g.discovery->stop();
  }
  std::vector<std::unique_ptr<detail::ServerLink>> links;
  {
    std::lock_guard lock(g.links_mutex);
    g.started = false;
    links = std::move(g.links);
    g.links.clear();
  }
  for (auto& link : links) {
    link->stop();
  }
  g.writer->stop();
  g.to_aggregating = LiveBus::Subscription();
  g.alarm_events = nullptr;
  if (g.aggregating) {
    g.aggregating->stop();
  }
  // Status after stop still lists the servers.
  std::lock_guard lock(g.links_mutex);
  g.links = std::move(links);
}

GatewayStatus Gateway::status() const {
  const Impl& g = *impl_;
  GatewayStatus s;
  {
    std::lock_guard lock(g.links_mutex);
    for (const auto& link : g.links) {
      s.servers.push_back(link->status());
    }
  }
  if (g.discovery) {
    s.discovery = g.discovery->status();
  }
  const detail::WriterStats w = g.writer->stats();
  s.samples_received = w.samples_received;
  s.samples_written = w.samples_written;
  s.samples_failed = w.samples_failed;
  s.events_written = w.events_written;
  s.queued = w.queued;
  s.buffer = g.store->stats();
  s.aggregating_port = g.aggregating ? g.aggregating->port() : 0;
  return s;
}

const KnowledgeLoop* Gateway::knowledge() const {
  return impl_->knowledge.get();
}

KnowledgeLoop* Gateway::knowledge() {
  return impl_->knowledge.get();
}

LiveBus& Gateway::live() {
  return impl_->bus;
}

Result<std::vector<opcua::Variant>> Gateway::call(std::string_view server, const std::string& object_path,
                                                  const std::string& method,
                                                  std::vector<opcua::Variant> inputs) {
  // The lock keeps the link alive through the call (stop() takes the links under it).
  std::lock_guard lock(impl_->links_mutex);
  for (auto& link : impl_->links) {
    if (link->status().name == server) {
      return link->call(object_path, method, std::move(inputs));
    }
  }
  return make_error(Errc::not_found, fmt::format("no server '{}'", server));
}

historian::Store& Gateway::store() {
  return *impl_->store;
}

}  // namespace sf::cloud
