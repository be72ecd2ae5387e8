#include "aggregating_server.hpp"

#include "alarm_condition.hpp"

#include <fmt/format.h>

#include "sf/cloud/value_mapping.hpp"
#include "sf/core/log.hpp"
#include "sf/opcua/status_codes.hpp"

namespace sf::cloud::detail {

namespace {

namespace ua = sf::opcua;
namespace srv = sf::opcua::server;
using historian::Micros;

// Backward reads and reads of "all values" fetch at most this many samples per request; a
// forward read returns them with a continuation point for the rest.
constexpr std::size_t kMaxPerRequest = 100'000;

// The historian's window [from, to) for a query (see read_raw_sorted for the semantics).
struct Fetch {
  historian::Timestamp from;
  historian::Timestamp to;
  std::size_t limit;
};

Fetch fetch_for(const srv::HistoryRawQuery& q, std::uint32_t page, std::uint32_t skip,
                std::optional<ua::DateTime> cursor_time) {
  const historian::Timestamp earliest = historian::from_micros(INT64_MIN / 2);
  const historian::Timestamp latest = historian::from_micros(INT64_MAX / 2);
  const bool forward = !q.start.is_min() && (q.end.is_min() || q.start <= q.end);
  if (forward) {
    Fetch f;
    f.from = to_timestamp(cursor_time ? std::max(*cursor_time, q.start) : q.start);
    f.to = q.end.is_min() ? latest
                          : (q.start == q.end ? to_timestamp(q.start) + Micros(1) : to_timestamp(q.end));
    // One more than the page shows whether a continuation point is due.
    f.limit = std::size_t{skip} + page + 1;
    return f;
  }
  // Backwards: end < t <= start, or t <= end; fetched oldest first and reversed by the caller.
  Fetch f;
  f.from = q.start.is_min() ? earliest : to_timestamp(q.end) + Micros(1);
  f.to = (q.start.is_min() ? to_timestamp(q.end) : to_timestamp(q.start)) + Micros(1);
  f.limit = kMaxPerRequest;
  return f;
}

std::string display_path(const historian::SeriesInfo& info) {
  // "/Objects/Demo/Temperature" → "Demo/Temperature": the Objects folder is the server's own.
  std::string_view path = info.browse_path;
  if (path.starts_with("/Objects/")) {
    path.remove_prefix(9);
  } else if (path.starts_with("/")) {
    path.remove_prefix(1);
  }
  return path.empty() ? info.node_id : std::string(path);
}

}  // namespace

srv::HistoryRawResult HistorianHistory::read_raw(const srv::HistoryRawQuery& query) {
  srv::HistoryRawResult result;
  const auto found = series_.find(query.node);
  if (found == series_.end()) {
    result.status = ua::status::BadNodeIdUnknown;
    return result;
  }
  std::optional<ua::DateTime> cursor_time;
  std::uint32_t skip = 0;
  if (!query.continuation_point.is_null() && !query.continuation_point.empty()) {
    auto cursor = srv::decode_history_cursor(query.node, query.continuation_point);
    if (!cursor) {
      result.status = ua::status::BadContinuationPointInvalid;
      return result;
    }
    cursor_time = cursor->time;
    skip = cursor->skip;
  }
  const auto page = static_cast<std::uint32_t>(
      query.max_values == 0 ? kMaxPerRequest : std::min<std::size_t>(query.max_values, kMaxPerRequest));
  const Fetch f = fetch_for(query, page, skip, cursor_time);
  auto samples = store_.read_raw(found->second, f.from, f.to, f.limit);
  if (!samples) {
    log::get("cloud")->warn("HistoryRead {}: {}", ua::to_string(query.node), samples.error().describe());
    result.status = ua::status::BadHistoryOperationInvalid;
    return result;
  }
  std::vector<ua::DataValue> values;
  values.reserve(samples->size());
  for (const historian::Sample& s : *samples) {
    values.push_back(to_data_value(s));
  }
  srv::HistoryRawQuery paged = query;
  paged.max_values = page;
  return srv::read_raw_sorted(paged, values);
}

srv::ServerConfig AggregatingServer::server_config(const AggregatingServerConfig& config) {
  srv::ServerConfig server_config;
  server_config.transport.host = config.host;
  server_config.transport.port = config.port;
  server_config.identity.application_uri = "urn:smartfactory:cloud:aggregating-server";
  server_config.identity.application_name = "smartfactory cloud aggregating server";
  return server_config;
}

AggregatingServer::AggregatingServer(const srv::ServerConfig& server_config, historian::Store& store)
    : history_(std::make_shared<HistorianHistory>(store)) {
  server_ = std::make_unique<srv::Server>(server_config);
  server_->with_address_space(
      [this](srv::AddressSpace& space) { ns_ = space.add_namespace(kCloudNamespaceUri); });
  server_->set_history_database(history_);
}

AggregatingServer::~AggregatingServer() {
  stop();
}

Status AggregatingServer::start() {
  return server_->start();
}

void AggregatingServer::stop() {
  if (server_) {
    server_->stop();
  }
}

std::uint16_t AggregatingServer::port() const {
  return server_->port();
}

// A FolderType object per path segment: "line-1", "line-1/Demo", ...
ua::NodeId AggregatingServer::folder_for(srv::AddressSpace& space, const std::string& path) {
  const ua::NodeId id(ns_, ua::String(path));
  if (space.contains(id)) {
    return id;
  }
  const auto slash = path.rfind('/');
  srv::ObjectSpec folder;
  folder.node_id = id;
  folder.browse_name =
      ua::QualifiedName(ns_, ua::String(slash == std::string::npos ? path : path.substr(slash + 1)));
  folder.parent = slash == std::string::npos ? ua::NodeId(0, ua::id::ObjectsFolder)
                                             : folder_for(space, path.substr(0, slash));
  folder.reference_type = ua::NodeId(0, ua::id::Organizes);
  folder.type_definition = ua::NodeId(0, ua::id::FolderType);
  (void)space.add_object(folder);
  return id;
}

void AggregatingServer::add_series(const historian::Series& series) {
  server_->loop().post([this, series] {
    if (nodes_.contains(series.id)) {
      return;
    }
    server_->with_address_space([&](srv::AddressSpace& space) {
      const std::string path = series.info.server + "/" + display_path(series.info);
      const auto slash = path.rfind('/');
      srv::VariableSpec spec;
      spec.node_id = ua::NodeId(ns_, ua::String(path));
      spec.browse_name = ua::QualifiedName(ns_, ua::String(path.substr(slash + 1)));
      spec.description = ua::LocalizedText("en", ua::String(series.info.server + " " + series.info.node_id));
      spec.parent = folder_for(space, path.substr(0, slash));
      spec.reference_type = ua::NodeId(0, ua::id::Organizes);
      spec.data_type = data_type_of(series.info.data_type);
      spec.access_level = srv::access_level::CurrentRead | srv::access_level::HistoryRead;
      spec.user_access_level = spec.access_level;
      spec.historizing = true;
      auto added = space.add_variable(spec);
      if (!added) {
        log::get("cloud")->warn("aggregating server: {}: {}", path, added.error().message);
        return;
      }
      nodes_[series.id] = *added;
      history_->map(*added, series.id);
    });
  });
}

void AggregatingServer::update(const LiveUpdate& update) {
  server_->loop().post([this, sample = update.sample] {
    const auto found = nodes_.find(sample.series);
    if (found == nodes_.end()) {
      return;
    }
    server_->with_address_space(
        [&](srv::AddressSpace& space) { (void)space.set_value(found->second, to_data_value(sample)); });
  });
}

void AggregatingServer::report(const Alarm& alarm) {
  server_->raise_event(ua::NodeId(0, ua::id::Server), condition_event(alarm, ns_));
}

void AggregatingServer::refresh_from(std::function<std::vector<Alarm>()> retained) {
  server_->set_condition_refresh([this, retained = std::move(retained)] {
    std::vector<ua::SubscriptionService::Event> events;
    for (const Alarm& alarm : retained()) {
      events.push_back(condition_event(alarm, ns_));
    }
    return events;
  });
}

}  // namespace sf::cloud::detail
