#include "server_link.hpp"

#include <fmt/format.h>

#include <chrono>

#include "model_walk.hpp"
#include "sf/cloud/value_mapping.hpp"
#include "sf/core/log.hpp"

namespace sf::cloud::detail {

namespace {

namespace ua = sf::opcua;
using namespace std::chrono_literals;

// BaseEventType fields the historian keeps (OPC 10000-5 §6.4.2), in this order.
const std::vector<std::string> kEventFields = {"EventId", "EventType",   "SourceNode", "SourceName",
                                               "Time",    "ReceiveTime", "Message",    "Severity"};

template <typename T>
const T* field(const std::vector<ua::Variant>& fields, std::size_t i) {
  return i < fields.size() ? fields[i].get_if<T>() : nullptr;
}

}  // namespace

ua::ClientConfig ServerLink::client_config(const ServerConfig& config) {
  ua::ClientConfig client;
  client.endpoint_url = config.url;
  client.session_name = fmt::format("smartfactory cloud gateway ({})", config.name);
  client.application_uri = "urn:smartfactory:cloud:gateway";
  client.request_timeout = 10s;
  return client;
}

ServerLink::ServerLink(ServerConfig config, ua::ClientConfig client, historian::Store& store,
                       SampleWriter& writer, LiveBus& bus,
                       std::function<void(const historian::Series&)> on_series, const Clock& clock)
    : config_(std::move(config)),
      clock_(clock),
      store_(store),
      writer_(writer),
      bus_(bus),
      on_series_(std::move(on_series)) {
  client_ = std::make_unique<ua::SyncClient>(std::move(client));
  client_->set_on_state([this](ua::ClientState state, const Status& why) {
    client_state_ = static_cast<int>(state);
    if (!why.ok()) {
      std::lock_guard lock(mutex_);
      last_error_ = why.error().message;
    }
  });
}

ServerLink::~ServerLink() {
  stop();
}

void ServerLink::start() {
  setup_thread_ = std::thread([this] { setup(); });
}

void ServerLink::stop() {
  {
    std::lock_guard lock(mutex_);
    stopping_ = true;
  }
  stop_wait_.notify_all();
  if (setup_thread_.joinable()) {
    setup_thread_.join();
  }
  if (client_) {
    client_->disconnect();
  }
  set_phase("stopped");
}

void ServerLink::set_phase(std::string phase, std::string error) {
  std::lock_guard lock(mutex_);
  phase_ = std::move(phase);
  if (!error.empty()) {
    last_error_ = std::move(error);
  }
}

Result<std::vector<ua::Variant>> ServerLink::call(const std::string& object_path, const std::string& method,
                                                  std::vector<ua::Variant> inputs) {
  if (static_cast<ua::ClientState>(client_state_.load()) != ua::ClientState::Connected) {
    return make_error(Errc::state, fmt::format("server '{}' is not connected", config_.name));
  }
  std::lock_guard lock(call_mutex_);
  auto node_of = [&](const std::string& path) -> Result<ua::NodeId> {
    if (auto known = resolved_.find(path); known != resolved_.end()) {
      return known->second;
    }
    auto found = resolve_browse_path(*client_, path);
    if (!found) {
      return found.error();
    }
    return resolved_.emplace(path, found->first).first->second;
  };
  auto object = node_of(object_path);
  if (!object) {
    return object.error();
  }
  auto method_node = node_of(object_path + "/" + method);
  if (!method_node) {
    return method_node.error();
  }
  return client_->call_method(*object, *method_node, std::move(inputs));
}

ServerStatus ServerLink::status() const {
  std::lock_guard lock(mutex_);
  ServerStatus s;
  s.name = config_.name;
  s.url = config_.url;
  const auto state = static_cast<ua::ClientState>(client_state_.load());
  s.connected = state == ua::ClientState::Connected;
  s.phase = phase_ == "subscribed" && state == ua::ClientState::Reconnecting ? "reconnecting" : phase_;
  s.series = series_count_.load();
  s.samples = samples_.load();
  s.events = events_.load();
  s.last_error = last_error_;
  s.warnings = warnings_;
  return s;
}

// Until the server answers, with a back-off from 250 ms to 10 s (the first connect has no
// automatic reconnect of its own).
Status ServerLink::connect_with_retry() {
  auto backoff = 250ms;
  while (true) {
    set_phase("connecting");
    const Status connected = client_->connect();
    if (connected) {
      return {};
    }
    log::get("cloud")->warn("{} ({}): {}; retrying in {} ms", config_.name, config_.url,
                            connected.error().message, backoff.count());
    set_phase("connecting", connected.error().message);
    std::unique_lock lock(mutex_);
    if (stop_wait_.wait_for(lock, backoff, [this] { return stopping_; })) {
      return make_error(Errc::state, "stopped");
    }
    backoff = std::min<std::chrono::milliseconds>(backoff * 2, 10s);
  }
}

void ServerLink::setup() {
  while (true) {
    if (!connect_with_retry()) {
      return;
    }
    const Status subscribed = subscribe_all();
    if (subscribed) {
      set_phase("subscribed");
      rediscover();
      return;
    }
    // A connection lost during discovery: start over with a new subscription. The states of
    // items made so far are kept aside, not freed: a late notification may still reach one.
    log::get("cloud")->warn("{}: setting up failed: {}", config_.name, subscribed.error().message);
    set_phase("connecting", subscribed.error().message);
    client_->disconnect();
    for (auto& [key, state] : series_) {
      retired_.push_back(std::move(state));
    }
    series_.clear();
    series_count_ = 0;
    subscription_.reset();
    events_subscribed_ = false;
    item_warnings_.clear();
    std::unique_lock lock(mutex_);
    if (stopping_ || stop_wait_.wait_for(lock, 1s, [this] { return stopping_; })) {
      return;
    }
  }
}

void ServerLink::rediscover() {
  if (config_.rediscover.count() <= 0) {
    return;
  }
  while (true) {
    {
      std::unique_lock lock(mutex_);
      if (stop_wait_.wait_for(lock, config_.rediscover, [this] { return stopping_; })) {
        return;
      }
    }
    if (static_cast<ua::ClientState>(client_state_.load()) != ua::ClientState::Connected) {
      continue;  // the client's reconnect is at work; its items come back by themselves
    }
    auto added = subscribe_new();
    if (!added) {
      log::get("cloud")->debug("{}: discovering again failed: {}", config_.name, added.error().message);
      continue;
    }
    if (!added->empty()) {
      log::get("cloud")->info("{}: {} more series subscribed (added to the server's model)", config_.name,
                              added->size());
      catch_up(*added);
    }
  }
}

Status ServerLink::subscribe_all() {
  set_phase("discovering");
  auto added = subscribe_new();
  if (!added) {
    return added.error();
  }
  for (const std::string& warning : status().warnings) {
    log::get("cloud")->warn("{}: {}", config_.name, warning);
  }
  if (config_.events && !events_subscribed_) {
    SF_TRY(subscribe_events(*subscription_));
    events_subscribed_ = true;
  }
  log::get("cloud")->info("{}: {} series subscribed{}", config_.name, series_.size(),
                          config_.events ? ", with events" : "");
  catch_up(*added);
  return {};
}

Result<std::vector<ServerLink::Subscribed>> ServerLink::subscribe_new() {
  auto namespaces = NamespaceTable::read(*client_);
  if (!namespaces) {
    return namespaces.error();
  }
  auto found = discover(*client_, *namespaces, config_.subscribe);
  if (!found) {
    return found.error();
  }
  if (!subscription_) {
    auto subscription =
        client_->create_subscription({.publishing_interval_ms = config_.publishing_interval_ms});
    if (!subscription) {
      return subscription.error();
    }
    subscription_ = *subscription;
  }
  std::vector<Subscribed> added;
  for (const DiscoveredVariable& v : found->variables) {
    if (series_.contains(v.key)) {
      continue;
    }
    historian::SeriesInfo info{config_.name, v.key, v.browse_path,
                               historian_type(v.data_type).value_or(historian::DataType::string), v.unit};
    auto id = store_.register_series(info);
    if (!id) {
      return id.error();
    }
    // The state exists before its item: the first notification may come before monitor_value returns.
    auto* state =
        series_.emplace(v.key, std::make_unique<SeriesState>(SeriesState{{*id, info}, std::nullopt}))
            .first->second.get();
    ++series_count_;
    if (on_series_) {
      on_series_(state->series);
    }
    ua::MonitoringParameters parameters;
    parameters.sampling_interval = config_.sampling_interval_ms;
    parameters.queue_size = config_.queue_size;
    parameters.discard_oldest = true;
    auto item =
        client_->monitor_value(*subscription_, ua::value_of(v.node), parameters,
                               [this, state](const ua::DataValue& value) { on_value(*state, value); });
    if (!item) {
      item_warnings_.push_back(fmt::format("{}: {}", v.browse_path, item.error().message));
    }
    added.push_back({v, state});
  }
  std::lock_guard lock(mutex_);
  warnings_ = found->warnings;
  warnings_.insert(warnings_.end(), item_warnings_.begin(), item_warnings_.end());
  return added;
}

// What the server kept while this gateway was away (stopped, crashed, or not started yet): each
// series from its newest stored sample on, read back with HistoryRead (OPC 10000-11 §6.4.3.2),
// after the subscription exists so that nothing falls between the two. The store skips the
// samples it holds already (their key), so the overlap costs nothing. Variables the server keeps
// no history of (no HistoryRead access, BadHistoryOperationUnsupported) have nothing to add.
void ServerLink::catch_up(const std::vector<Subscribed>& added) {
  std::uint64_t caught = 0;
  const ua::DateTime end = ua::DateTime::from_system_clock(clock_.utc_now() + 1s);
  for (const auto& [variable, state] : added) {
    const historian::Series& series = state->series;
    auto latest = store_.latest(series.id);
    ua::HistoryRawParams params;
    // The epoch rather than an open bound: with one bound open a raw read counts values back.
    params.start =
        latest && *latest ? to_date_time((*latest)->source_time) : ua::DateTime::from_unix_seconds(0);
    params.end = end;
    params.max_values = 1000;
    auto values = client_->history_read_raw(variable.node, params);
    if (!values) {
      continue;
    }
    std::optional<historian::Sample> previous;
    for (const ua::DataValue& value : *values) {
      historian::Sample sample = to_sample(series.id, value, now());
      if (previous && sample.source_time == previous->source_time) {
        sample.seq = previous->seq + 1;
      }
      previous = sample;
      bus_.publish(LiveUpdate{&series.info, sample, true});
      writer_.push(std::move(sample));
      ++caught;
    }
  }
  if (caught > 0) {
    samples_ += caught;
    log::get("cloud")->info("{}: {} samples read back from the server's history", config_.name, caught);
  }
}

Status ServerLink::subscribe_events(ua::SyncClient::SubscriptionId subscription) {
  auto item = client_->monitor_events(subscription, ua::NodeId(0, ua::id::Server),
                                      ua::select_event_fields(kEventFields),
                                      [this](const std::vector<ua::Variant>& fields) { on_event(fields); });
  if (!item) {
    return item.error();
  }
  return {};
}

// Notifications of one item arrive in order. A re-created item first reports the current value
// again: the same source time, value and status as the last sample, dropped here. Several
// values with one source time are numbered (seq), which keeps them apart in the historian.
historian::Timestamp ServerLink::now() const {
  return std::chrono::time_point_cast<historian::Micros>(clock_.utc_now());
}

void ServerLink::on_value(SeriesState& state, const ua::DataValue& value) {
  historian::Sample sample = to_sample(state.series.id, value, now());
  if (state.last && sample.source_time == state.last->source_time) {
    if (sample.value == state.last->value && sample.status == state.last->status) {
      return;
    }
    sample.seq = state.last->seq + 1;
  }
  state.last = sample;
  ++samples_;
  bus_.publish(LiveUpdate{&state.series.info, sample, false});
  writer_.push(std::move(sample));
}

void ServerLink::on_event(const std::vector<ua::Variant>& fields) {
  historian::Event event;
  event.server = config_.name;
  if (const auto* id = field<ua::ByteString>(fields, 0)) {
    event.event_id = id->bytes();
  }
  if (const auto* type = field<ua::NodeId>(fields, 1)) {
    event.event_type = ua::to_string(*type);
  }
  if (const auto* source = field<ua::NodeId>(fields, 2)) {
    event.source_node = ua::to_string(*source);
  }
  if (const auto* name = field<ua::String>(fields, 3)) {
    event.source_name = name->str();
  }
  const auto* time = field<ua::DateTime>(fields, 4);
  event.time = time != nullptr ? to_timestamp(*time) : now();
  const auto* receive = field<ua::DateTime>(fields, 5);
  event.receive_time = receive != nullptr ? to_timestamp(*receive) : now();
  if (const auto* message = field<ua::LocalizedText>(fields, 6)) {
    event.message = message->text.str();
  }
  if (const auto* severity = field<std::uint16_t>(fields, 7)) {
    event.severity = *severity;
  }
  ++events_;
  bus_.publish(event);
  writer_.push(std::move(event));
}

}  // namespace sf::cloud::detail
