// LineCloud and AxisRecorder (line_cloud.hpp).
#include "line_cloud.hpp"

#include <algorithm>
#include <cctype>

#include <fmt/format.h>

#include "sf/cloud/config.hpp"
#include "sf/factory/line_supervisor.hpp"
#include "sf/historian/types.hpp"
#include "sf/opcua/client/security_setup.hpp"
#include "sf/opcua/security/provisioning.hpp"

namespace sf::bench {
namespace {

namespace fs = std::filesystem;

std::int64_t micros(std::chrono::system_clock::time_point t) {
  return std::chrono::duration_cast<std::chrono::microseconds>(t.time_since_epoch()).count();
}

// The configuration `smartfactory line --historian` writes for its cloud (into dir/config), with
// the endpoints the line's processes reported.
Result<std::pair<cloud::GatewayConfig, line::Layout>> line_gateway_config(
    const fs::path& smartfactory, const fs::path& dir, const std::vector<LineProcessInfo>& processes) {
  factory::LineOptions o;
  o.program = smartfactory;
  o.run_dir = dir;
  o.historian = "sqlite:" + (dir / "history.db").string();
  o.opcua_base_port = 0;
  auto plan = factory::plan_line(o);
  if (!plan) {
    return plan.error();
  }
  SF_TRY(factory::write_cloud_config(*plan));
  auto config = cloud::load_gateway_config(plan->options.cloud_config);
  if (!config) {
    return config.error();
  }
  for (auto& server : config->servers) {
    const auto it = std::find_if(processes.begin(), processes.end(),
                                 [&](const LineProcessInfo& p) { return p.name == server.name; });
    if (it == processes.end() || it->opcua.empty()) {
      return make_error(Errc::not_found, fmt::format("the line has no OPC UA server {}", server.name));
    }
    server.url = it->opcua;
  }
  config->aggregating_server.enabled = false;
  return std::make_pair(std::move(*config), std::move(plan->layout));
}

// Each connection's security as `smartfactory cloud` applies it: the installation's PKI folder.
cloud::GatewayOptions gateway_options(const std::string& pki) {
  cloud::GatewayOptions options;
  const std::string folder = pki.empty() ? opcua::security::default_pki_dir() : pki;
  options.configure_client = [folder](const cloud::ServerConfig& server, opcua::ClientConfig& client) {
    opcua::ClientSecuritySettings settings;
    settings.pki = folder;
    settings.security = server.security.security;
    return opcua::configure_client_security(settings, client);
  };
  return options;
}

}  // namespace

Result<std::unique_ptr<LineCloud>> LineCloud::start(const fs::path& smartfactory, const fs::path& dir,
                                                    const std::vector<LineProcessInfo>& processes,
                                                    const fs::path& web_root, const fs::path& users) {
  auto config = line_gateway_config(smartfactory, dir, processes);
  if (!config) {
    return config.error();
  }
  std::unique_ptr<LineCloud> cloud(new LineCloud());
  cloud->layout_ = std::move(config->second);
  cloud->servers_ = config->first.servers;
  const std::string pki = config->first.pki;
  auto gateway = cloud::Gateway::create(std::move(config->first), gateway_options(pki));
  if (!gateway) {
    return gateway.error();
  }
  cloud->gateway_ = std::move(*gateway);
  SF_TRY(cloud->gateway_->start());
  dashboard::DashboardConfig dc;
  dc.http.host = "127.0.0.1";
  dc.http.port = 0;
  dc.http.threads = 2;  // as `smartfactory cloud`
  dc.http.static_root = web_root;
  dc.users = users;
  auto board = dashboard::Dashboard::create(*cloud->gateway_, cloud->layout_, std::move(dc));
  if (!board) {
    return board.error();
  }
  cloud->dashboard_ = std::move(*board);
  auto port = cloud->dashboard_->start();
  if (!port) {
    return port.error();
  }
  cloud->port_ = *port;
  return cloud;
}

LineCloud::~LineCloud() {
  if (dashboard_) {
    dashboard_->stop();
  }
  if (gateway_) {
    gateway_->stop();
  }
}

const cloud::ServerConfig* LineCloud::server(std::string_view name) const {
  const auto it = std::find_if(servers_.begin(), servers_.end(),
                               [&](const cloud::ServerConfig& s) { return s.name == name; });
  return it == servers_.end() ? nullptr : &*it;
}

LiveStreamCounts LineCloud::live_counts() {
  for (const auto& c : dashboard_->status().http.live_clients) {
    clients_[c.id] = {c.sent, c.dropped};
  }
  LiveStreamCounts sum;
  for (const auto& [id, c] : clients_) {
    sum.sent += c.sent;
    sum.dropped += c.dropped;
  }
  return sum;
}

bool is_axis_position(const historian::SeriesInfo& series, const std::string& robot) {
  constexpr std::string_view kAxis = "/Tags/axis";
  constexpr std::string_view kPosition = ".position";
  const std::string_view path = series.browse_path;
  const auto at = path.rfind(kAxis);
  if (series.server != robot || at == std::string_view::npos || !path.ends_with(kPosition)) {
    return false;
  }
  const auto digits = path.substr(at + kAxis.size(), path.size() - at - kAxis.size() - kPosition.size());
  return !digits.empty() && std::all_of(digits.begin(), digits.end(),
                                        [](char c) { return std::isdigit(static_cast<unsigned char>(c)); });
}

AxisRecorder::AxisRecorder(cloud::LiveBus& bus, std::string robot) : robot_(std::move(robot)) {
  subscription_ = bus.subscribe([this](const cloud::LiveUpdate& u) { on_value(u); });
}

void AxisRecorder::on_value(const cloud::LiveUpdate& u) {
  const auto now = std::chrono::system_clock::now();
  if (u.replayed || u.series == nullptr || !is_axis_position(*u.series, robot_)) {
    return;
  }
  const auto id = historian::series_id(u.series->server, u.series->node_id);
  const std::lock_guard lock(mutex_);
  samples_.push_back({id, historian::to_micros(u.sample.source_time), micros(now)});
  ++counts_[id];
}

std::vector<std::int64_t> AxisRecorder::moving_series(std::size_t changes) const {
  const std::lock_guard lock(mutex_);
  std::vector<std::int64_t> out;
  for (const auto& [id, n] : counts_) {
    if (n >= changes) {
      out.push_back(id);
    }
  }
  return out;
}

std::vector<GatewaySample> AxisRecorder::samples() const {
  const std::lock_guard lock(mutex_);
  return samples_;
}

}  // namespace sf::bench
