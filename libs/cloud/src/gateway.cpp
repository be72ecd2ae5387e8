#include "sf/cloud/gateway.hpp"

#include <fmt/format.h>

#include "aggregating_server.hpp"
#include "sample_writer.hpp"
#include "server_link.hpp"
#include "sf/core/log.hpp"

namespace sf::cloud {

struct Gateway::Impl {
  GatewayConfig config;
  LiveBus bus;
  std::unique_ptr<historian::BufferedStore> store;
  std::unique_ptr<detail::SampleWriter> writer;
  std::unique_ptr<detail::AggregatingServer> aggregating;
  LiveBus::Subscription to_aggregating;
  std::vector<std::unique_ptr<detail::ServerLink>> links;
  bool started = false;
};

Result<std::unique_ptr<Gateway>> Gateway::create(GatewayConfig config, Clock& clock,
                                                 CommitObserver on_commit) {
  auto impl = std::make_unique<Impl>();
  historian::BufferOptions buffer;
  buffer.directory = config.historian.buffer;
  auto store = historian::BufferedStore::open(config.historian.url, buffer, clock);
  if (!store) {
    return store.error().with_context(fmt::format("historian {}", config.historian.url));
  }
  impl->store = std::move(*store);
  impl->writer = std::make_unique<detail::SampleWriter>(
      *impl->store, config.historian.batch, config.historian.flush_interval, std::move(on_commit));
  impl->config = std::move(config);
  return std::unique_ptr<Gateway>(new Gateway(std::move(impl)));
}

Gateway::Gateway(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}

Gateway::~Gateway() {
  stop();
}

Status Gateway::start() {
  if (impl_->started) {
    return {};
  }
  Impl& g = *impl_;
  std::function<void(const historian::Series&)> on_series;
  if (g.config.aggregating_server.enabled) {
    g.aggregating = std::make_unique<detail::AggregatingServer>(g.config.aggregating_server, *g.store);
    if (auto st = g.aggregating->start(); !st) {
      g.aggregating.reset();
      return st.error().with_context("aggregating server");
    }
    g.to_aggregating =
        g.bus.subscribe([server = g.aggregating.get()](const LiveUpdate& u) { server->update(u); });
    on_series = [server = g.aggregating.get()](const historian::Series& s) { server->add_series(s); };
    // Series known from earlier runs have history already: show them from the start.
    if (auto known = g.store->list_series()) {
      for (const historian::Series& s : *known) {
        g.aggregating->add_series(s);
      }
    }
  }
  for (const ServerConfig& server : g.config.servers) {
    g.links.push_back(std::make_unique<detail::ServerLink>(server, *g.store, *g.writer, g.bus, on_series));
  }
  for (auto& link : g.links) {
    link->start();
  }
  g.started = true;
  log::get("cloud")->info(
      "gateway started: {} servers, historian {}{}", g.links.size(), g.config.historian.url,
      g.aggregating ? fmt::format(", aggregating server on port {}", g.aggregating->port()) : "");
  return {};
}

void Gateway::stop() {
  Impl& g = *impl_;
  for (auto& link : g.links) {
    link->stop();
  }
  g.writer->stop();
  g.to_aggregating = LiveBus::Subscription();
  if (g.aggregating) {
    g.aggregating->stop();
  }
  g.started = false;
}

GatewayStatus Gateway::status() const {
  const Impl& g = *impl_;
  GatewayStatus s;
  for (const auto& link : g.links) {
    s.servers.push_back(link->status());
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

LiveBus& Gateway::live() {
  return impl_->bus;
}

historian::Store& Gateway::store() {
  return *impl_->store;
}

}  // namespace sf::cloud
