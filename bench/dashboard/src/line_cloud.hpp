// The cloud of a running line in the benchmark's process: what `smartfactory line --historian
// --http` runs as its `cloud` process (factory::cloud_config_yaml's gateway configuration: every
// controller and the order service, the historian, the knowledge loop; the dashboard on it), less
// the aggregating OPC UA server (history for supervisory clients, not on the live path). The
// axis recorder watches the gateway's live bus, as bench_cloud_latency does.
#pragma once

#include <cstdint>
#include <filesystem>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "sf/bench/dashboard.hpp"
#include "sf/bench/running_line.hpp"
#include "sf/cloud/gateway.hpp"
#include "sf/dashboard/dashboard.hpp"
#include "sf/line/layout.hpp"

namespace sf::bench {

class LineCloud {
 public:
  // The gateway connected to the line's `processes` and the dashboard listening on a free port of
  // 127.0.0.1, serving `web_root`, its users from `users`. Files go to `dir`.
  static Result<std::unique_ptr<LineCloud>> start(const std::filesystem::path& smartfactory,
                                                  const std::filesystem::path& dir,
                                                  const std::vector<LineProcessInfo>& processes,
                                                  const std::filesystem::path& web_root,
                                                  const std::filesystem::path& users);
  ~LineCloud();
  LineCloud(const LineCloud&) = delete;
  LineCloud& operator=(const LineCloud&) = delete;

  [[nodiscard]] std::uint16_t port() const { return port_; }
  [[nodiscard]] cloud::Gateway& gateway() { return *gateway_; }
  [[nodiscard]] const line::Layout& layout() const { return layout_; }
  // The gateway's settings for the server `name`; nullptr when it has none.
  [[nodiscard]] const cloud::ServerConfig* server(std::string_view name) const;
  // Sent and dropped updates of every live client seen so far (poll while they are connected).
  LiveStreamCounts live_counts();

 private:
  LineCloud() = default;

  line::Layout layout_;
  std::vector<cloud::ServerConfig> servers_;
  std::unique_ptr<cloud::Gateway> gateway_;
  std::unique_ptr<dashboard::Dashboard> dashboard_;
  std::uint16_t port_ = 0;
  std::map<std::uint64_t, LiveStreamCounts> clients_;  // by live client id: its latest counts
};

// `Tags/axis<N>.position` of the machine `robot` (its OPC UA model, machine_model.cpp)?
bool is_axis_position(const historian::SeriesInfo& series, const std::string& robot);

// Every axis position sample of one robot the gateway's live bus delivers, with its arrival.
class AxisRecorder {
 public:
  AxisRecorder(cloud::LiveBus& bus, std::string robot);
  // The axis series that delivered at least `changes` values.
  [[nodiscard]] std::vector<std::int64_t> moving_series(std::size_t changes) const;
  [[nodiscard]] std::vector<GatewaySample> samples() const;

 private:
  void on_value(const cloud::LiveUpdate& update);

  std::string robot_;
  mutable std::mutex mutex_;
  std::vector<GatewaySample> samples_;
  std::map<std::int64_t, std::size_t> counts_;
  cloud::LiveBus::Subscription subscription_;  // last: unsubscribed before the rest goes
};

}  // namespace sf::bench
