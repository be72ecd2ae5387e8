// What the routes share: the gateway, the books, the sessions, and the checks every route makes
// (a session of a role; the CSRF token on writes).
#pragma once

#include <atomic>
#include <map>
#include <mutex>
#include <optional>
#include <string>
#include <variant>

#include <nlohmann/json.hpp>

#include "sf/cloud/gateway.hpp"
#include "sf/dashboard/dashboard.hpp"
#include "sf/dashboard/machine_board.hpp"
#include "sf/dashboard/order_book.hpp"
#include "sf/dashboard/sessions.hpp"
#include "sf/web/router.hpp"
#include "sf/web/server.hpp"

namespace sf::dashboard {

struct Context {
  Context(cloud::Gateway& g, const line::Layout& l, DashboardConfig c, const Clock& k,
          std::shared_ptr<opcua::security::UsersFile> users)
      : gateway(g),
        layout(l),
        config(std::move(c)),
        clock(k),
        sessions(std::move(users), k, config.session_idle),
        order_limit(k, config.orders_burst, config.order_period),
        login_limit(k, 10, std::chrono::seconds(6)),
        machines(l) {}

  cloud::Gateway& gateway;
  const line::Layout& layout;
  DashboardConfig config;
  const Clock& clock;
  Sessions sessions;
  RateLimiter order_limit;  // per user
  RateLimiter login_limit;  // per user name tried
  OrderBook orders;
  MachineBoard machines;
  // Set once listening, cleared before it stops: publish() from the bus's threads holds the
  // mutex, so the server is never stopped under a publication.
  void set_server(web::HttpServer* s);

  [[nodiscard]] historian::Timestamp now() const;
  // The gateway server of the order service (the one whose series are below /Objects/OrderService).
  [[nodiscard]] std::optional<std::string> order_server();
  // A series of the historian by its id: Errc::not_found when the store has none. The list is
  // read from the store again only when an id or the order service is not in the one kept (ids
  // never change; series are only added).
  [[nodiscard]] Result<historian::Series> series(historian::SeriesId id);
  void publish(const std::string& topic, const nlohmann::json& value) const;

 private:
  Status reload_series();

  mutable std::mutex server_mutex_;
  web::HttpServer* server_ = nullptr;
  std::mutex series_mutex_;
  std::map<historian::SeriesId, historian::Series> series_;
  std::optional<std::string> order_server_;
};

// The request's session when it has one of at least `role`; writes (not GET/HEAD) must carry the
// session's CSRF token in X-CSRF-Token. Otherwise the response to send: 401 or 403.
std::variant<Session, web::Response> authorize(Context& c, const web::Request& request, Role role);

// A handler that runs `f(request, session)` for a session of at least `role` (authorize()).
template <typename F>
web::Handler guarded(Context& c, Role role, F f) {
  return [&c, role, f = std::move(f)](const web::Request& r) -> web::Response {
    auto who = authorize(c, r, role);
    if (auto* refused = std::get_if<web::Response>(&who)) {
      return std::move(*refused);
    }
    return f(r, std::get<Session>(who));
  };
}

// An integer query parameter in [lo, hi], `fallback` when absent; the error names the range.
Result<std::int64_t> int_param(const web::Request& r, const std::string& name, std::int64_t fallback,
                               std::int64_t lo, std::int64_t hi);

// An alarm as the API shows it.
nlohmann::json alarm_json(const cloud::Alarm& a);
// An alarm's historian event (cloud::alarm_event) as the API shows alarms; nullopt when it is not one.
std::optional<nlohmann::json> alarm_of(const historian::Event& e);

// The route table (routes_*.cpp).
Status add_session_routes(web::Router& router, Context& c);
Status add_order_routes(web::Router& router, Context& c);
Status add_machine_routes(web::Router& router, Context& c);
Status add_history_routes(web::Router& router, Context& c);

// An order as the API shows it (openapi.yaml Order).
nlohmann::json order_json(const OrderView& o);
// A Gateway::call error as the API answers it: 503 while the server is away, 404, 409 for
// BadInvalidState, else 502 with the server's message.
web::Response call_error(const Error& error, std::string_view what);

}  // namespace sf::dashboard
