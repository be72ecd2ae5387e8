// The cloud's aggregating OPC UA server (paper Fig. 6: supervisory clients see history): one
// Variable per historian series, under Objects/<server name>/<browse path>, holding the live value
// and answering HistoryRead (raw) from the historian; the knowledge loop's alarms are its
// Server object's events (alarm_condition.hpp).
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <unordered_map>

#include "sf/cloud/config.hpp"
#include "sf/cloud/knowledge_loop.hpp"
#include "sf/cloud/live_bus.hpp"
#include "sf/historian/store.hpp"
#include "sf/opcua/server/history.hpp"
#include "sf/opcua/server/server.hpp"

namespace sf::cloud::detail {

inline constexpr std::string_view kCloudNamespaceUri = "urn:smartfactory:cloud";

// HistoryRead of a series node → historian read_raw. Runs on the server's loop thread.
class HistorianHistory final : public opcua::server::HistoryDatabase {
 public:
  explicit HistorianHistory(historian::Store& store) : store_(store) {}
  void map(const opcua::NodeId& node, historian::SeriesId series) { series_[node] = series; }
  opcua::server::HistoryRawResult read_raw(const opcua::server::HistoryRawQuery& query) override;

 private:
  historian::Store& store_;
  std::unordered_map<opcua::NodeId, historian::SeriesId> series_;
};

class AggregatingServer {
 public:
  // The server's settings for `config` (address, identity), before security is applied.
  static opcua::server::ServerConfig server_config(const AggregatingServerConfig& config);
  AggregatingServer(const opcua::server::ServerConfig& server_config, historian::Store& store);
  ~AggregatingServer();
  AggregatingServer(const AggregatingServer&) = delete;
  AggregatingServer& operator=(const AggregatingServer&) = delete;

  Status start();
  void stop();
  [[nodiscard]] std::uint16_t port() const;

  // Any thread. Adds the series' Variable (and the folders of its path) once.
  void add_series(const historian::Series& series);
  // Any thread. The Variable's value follows the live data.
  void update(const LiveUpdate& update);
  // Any thread. A raise, clear or acknowledgement as an AlarmConditionType event of the Server
  // object (OPC 10000-9 §5.8), to every client subscribed to its events.
  void report(const Alarm& alarm);
  // Any thread. What a client's ConditionRefresh (OPC 10000-9 §5.5.7) reports: the alarms
  // `retained` returns (called on the server's loop thread).
  void refresh_from(std::function<std::vector<Alarm>()> retained);

 private:
  opcua::NodeId folder_for(opcua::server::AddressSpace& space, const std::string& path);

  std::unique_ptr<opcua::server::Server> server_;
  std::shared_ptr<HistorianHistory> history_;
  std::uint16_t ns_ = 0;
  // Loop thread only.
  std::unordered_map<historian::SeriesId, opcua::NodeId> nodes_;
};

}  // namespace sf::cloud::detail
