// The dashboard (paper Fig. 1: client terminals and consumers' devices on the cloud): the REST
// API and live stream of libs/dashboard/openapi.yaml over the cloud gateway (its live bus,
// historian, connections to the shop floor and knowledge loop), served by sf::web::HttpServer
// with the pages of the web root.
//
//   auto dashboard = Dashboard::create(*gateway, layout, config);
//   auto port = (*dashboard)->start();       // replays the historian's orders, then serves
//   ...
//   (*dashboard)->stop();
//
// Orders go to the order service through the gateway (SubmitOrder, CancelOrder), PackML
// commands to the machines' methods; both as the gateway's connection's user. What the API
// lets a web user do is decided here by the user's web role (sessions.hpp).
#pragma once

#include <chrono>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "sf/cloud/gateway.hpp"
#include "sf/core/clock.hpp"
#include "sf/core/result.hpp"
#include "sf/line/layout.hpp"
#include "sf/web/server.hpp"

namespace sf::dashboard {

struct DashboardConfig {
  web::ServerConfig http;       // listen address, web root, limits, TLS (live_access is set here)
  std::filesystem::path users;  // the users file (`smartfactory opcua users`); required
  // Secure on the session cookie (RFC 6265 §4.1.2.5): always with http.tls; set it also behind a
  // proxy that terminates TLS.
  bool secure_cookies = false;
  double orders_burst = 5;                         // orders a user may place at once,
  std::chrono::milliseconds order_period{12'000};  // then one per period
  std::chrono::seconds session_idle{std::chrono::hours(8)};
};

struct DashboardStatus {
  std::size_t orders = 0;
  std::size_t sessions = 0;
  std::uint64_t rejected_events = 0;  // order steps or inspections that could not be read
  web::ServerStats http;
};

class Dashboard {
 public:
  // `gateway` and `layout` must outlive the dashboard. Errors: an unreadable users file.
  static Result<std::unique_ptr<Dashboard>> create(cloud::Gateway& gateway, const line::Layout& layout,
                                                   DashboardConfig config,
                                                   const Clock& clock = SteadyClock::instance());
  ~Dashboard();
  Dashboard(const Dashboard&) = delete;
  Dashboard& operator=(const Dashboard&) = delete;

  // Rebuilds the order book from the historian, follows the live bus, listens: the port.
  Result<std::uint16_t> start();
  void stop();
  [[nodiscard]] DashboardStatus status() const;
  // The API's routes as (method, pattern) once started (what openapi.yaml must describe).
  [[nodiscard]] std::vector<std::pair<std::string, std::string>> routes() const;

  struct Impl;

 private:
  explicit Dashboard(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

// The OpenAPI 3 description served at /api/openapi.yaml (libs/dashboard/openapi.yaml, built in).
std::string_view openapi_yaml();

}  // namespace sf::dashboard
