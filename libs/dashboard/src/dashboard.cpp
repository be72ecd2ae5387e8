// Dashboard (dashboard.hpp): the books fed by the live bus, the routes, the live topics.
#include "sf/dashboard/dashboard.hpp"

#include <charconv>

#include <fmt/format.h>

#include "context.hpp"
#include "json_values.hpp"
#include "sf/cloud/knowledge_loop.hpp"
#include "sf/core/log.hpp"

namespace sf::dashboard {

namespace {

constexpr std::string_view kInspectionPath = "/Objects/OrderService/LastInspection";
constexpr std::string_view kOrderServicePath = "/Objects/OrderService/";
// The most events and inspections read back at start: the book of a long-running line.
constexpr std::size_t kReplayLimit = 1'000'000;

}  // namespace

historian::Timestamp Context::now() const {
  return std::chrono::time_point_cast<historian::Micros>(clock.utc_now());
}

Status Context::reload_series() {
  auto all = gateway.store().list_series();
  if (!all) {
    return all.error();
  }
  for (auto& s : *all) {
    if (!order_server_ && s.info.browse_path.starts_with(kOrderServicePath)) {
      order_server_ = s.info.server;
    }
    series_.insert_or_assign(s.id, std::move(s));
  }
  return {};
}

std::optional<std::string> Context::order_server() {
  std::lock_guard lock(series_mutex_);
  if (!order_server_ && !reload_series()) {
    return std::nullopt;
  }
  return order_server_;
}

Result<historian::Series> Context::series(historian::SeriesId id) {
  std::lock_guard lock(series_mutex_);
  if (!series_.contains(id)) {
    SF_TRY(reload_series());
  }
  if (auto it = series_.find(id); it != series_.end()) {
    return it->second;
  }
  return make_error(Errc::not_found, fmt::format("no series {}", id));
}

void Context::set_server(web::HttpServer* s) {
  std::lock_guard lock(server_mutex_);
  server_ = s;
}

void Context::publish(const std::string& topic, const nlohmann::json& value) const {
  std::lock_guard lock(server_mutex_);
  if (server_ != nullptr) {
    server_->publish(topic, value);
  }
}

// An integer query parameter in [lo, hi], `fallback` when absent.
Result<std::int64_t> int_param(const web::Request& r, const std::string& name, std::int64_t fallback,
                               std::int64_t lo, std::int64_t hi) {
  const auto it = r.query_params.find(name);
  if (it == r.query_params.end()) {
    return fallback;
  }
  std::int64_t n = 0;
  const auto& text = it->second;
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), n);
  if (error != std::errc{} || end != text.data() + text.size() || n < lo || n > hi) {
    return make_error(Errc::invalid_argument,
                      fmt::format("{} must be a whole number from {} to {}", name, lo, hi));
  }
  return n;
}

nlohmann::json alarm_json(const cloud::Alarm& a) {
  return {{"id", a.id},
          {"change", to_string(a.change)},
          {"rule", a.rule},
          {"entity", a.entity},
          {"message", a.message},
          {"facts", a.facts},
          {"active", a.active},
          {"acked", a.acked},
          {"acked_by", a.acked_by},
          {"ack_comment", a.ack_comment},
          {"time", time_text(a.time)}};
}

std::optional<nlohmann::json> alarm_of(const historian::Event& e) {
  auto fields = nlohmann::json::parse(e.fields, nullptr, false);
  if (fields.is_discarded() || !fields.is_object()) {
    return std::nullopt;
  }
  cloud::Alarm a;
  const std::string change = fields.value("change", "raised");
  for (const auto known :
       {cloud::AlarmChange::raised, cloud::AlarmChange::cleared, cloud::AlarmChange::acknowledged}) {
    if (cloud::to_string(known) == change) {
      a.change = known;
    }
  }
  // The message of a change other than the raise starts with it ("cleared: ...").
  a.message = e.message;
  if (change != "raised" && a.message.starts_with(change + ": ")) {
    a.message.erase(0, change.size() + 2);
  }
  a.id = fields.value("id", "");
  a.rule = fields.value("rule", "");
  a.entity = e.source_node;
  a.facts = fields.value("facts", std::vector<std::string>{});
  a.active = fields.value("active", false);
  a.acked = fields.value("acked", false);
  a.acked_by = fields.value("acked_by", "");
  a.ack_comment = fields.value("ack_comment", "");
  a.time = e.time;
  return alarm_json(a);
}

std::variant<Session, web::Response> authorize(Context& c, const web::Request& request, Role role) {
  auto session = c.sessions.find(request.headers.get("Cookie"));
  if (!session) {
    return web::error_response(401, "log in first (POST /api/session)");
  }
  if (session->role < role) {
    return web::error_response(403, fmt::format("the role {} may not do this (needs {})",
                                                to_string(session->role), to_string(role)));
  }
  if (request.method != "GET" && request.method != "HEAD") {
    const auto token = request.headers.get("X-CSRF-Token");
    if (!token || *token != session->csrf) {
      return web::error_response(403, "missing or wrong X-CSRF-Token (the session's csrf)");
    }
  }
  return std::move(*session);
}

struct Dashboard::Impl {
  Impl(cloud::Gateway& g, const line::Layout& l, DashboardConfig c, const Clock& k,
       std::shared_ptr<opcua::security::UsersFile> users)
      : context(g, l, std::move(c), k, std::move(users)) {}

  void replay();
  void on_value(const cloud::LiveUpdate& u);
  void on_event(const historian::Event& e);
  web::LiveAccess live_access(const web::Request& upgrade);

  Context context;
  std::unique_ptr<web::HttpServer> server;
  std::vector<std::pair<std::string, std::string>> routes;
  cloud::LiveBus::Subscription subscription;
};

void Dashboard::Impl::replay() {
  auto& store = context.gateway.store();
  historian::EventQuery owners{historian::Timestamp{}, context.now() + std::chrono::hours(1),
                               std::string(kDashboardServer), kReplayLimit};
  if (auto events = store.read_events(owners)) {
    for (const auto& e : *events) {
      context.orders.on_event(e);
    }
  }
  const auto orders = context.order_server();
  if (!orders) {
    return;
  }
  historian::EventQuery steps{historian::Timestamp{}, context.now() + std::chrono::hours(1), *orders,
                              kReplayLimit};
  if (auto events = store.read_events(steps)) {
    for (const auto& e : *events) {
      context.orders.on_event(e);
    }
  }
  auto series = store.list_series();
  for (const auto& s : series ? *series : std::vector<historian::Series>{}) {
    if (s.info.server != *orders || s.info.browse_path != kInspectionPath) {
      continue;
    }
    auto samples =
        store.read_raw(s.id, historian::Timestamp{}, context.now() + std::chrono::hours(1), kReplayLimit);
    for (const auto& sample : samples ? *samples : std::vector<historian::Sample>{}) {
      if (const auto* text = std::get_if<std::string>(&sample.value)) {
        context.orders.on_inspection(*text, sample.source_time);
      }
    }
  }
  log::get("dashboard")->info("order book: {} orders from the historian", context.orders.size());
}

void Dashboard::Impl::on_value(const cloud::LiveUpdate& u) {
  if (u.series == nullptr) {
    return;
  }
  if (u.series->browse_path == kInspectionPath) {
    if (const auto* text = std::get_if<std::string>(&u.sample.value)) {
      if (auto id = context.orders.on_inspection(*text, u.sample.source_time)) {
        if (auto o = context.orders.find(*id)) {
          context.publish("order/" + *id, order_json(*o));
        }
      }
    }
  }
  if (auto machine = context.machines.on_value(u)) {
    if (auto m = context.machines.machine(*machine, false)) {
      context.publish("machine/" + *machine, *m);
    }
    context.publish("machines", context.machines.all());
  }
  if (!u.replayed) {
    const auto id = historian::series_id(u.series->server, u.series->node_id);
    context.publish(fmt::format("series/{}", id),
                    {{"t", time_text(u.sample.source_time)}, {"v", value_json(u.sample.value)}});
  }
}

void Dashboard::Impl::on_event(const historian::Event& e) {
  if (e.server == cloud::kKnowledgeServer) {
    // The alarm that changed (raised, cleared): this runs inside the knowledge loop's sink, where
    // its list cannot be asked for; a client reads the list again (GET /api/alarms).
    if (auto alarm = alarm_of(e)) {
      context.publish("alarms", *alarm);
    }
    return;
  }
  if (auto id = context.orders.on_event(e)) {
    if (auto o = context.orders.find(*id)) {
      auto json = order_json(*o);
      context.publish("order/" + *id, json);
      context.publish("orders", json);
    }
  }
}

web::LiveAccess Dashboard::Impl::live_access(const web::Request& upgrade) {
  auto session = context.sessions.find(upgrade.headers.get("Cookie"));
  if (!session) {
    return web::error_response(401, "log in first (POST /api/session)");
  }
  // A page of another site may open a WebSocket to us with the user's cookie (browsers send
  // Origin on every WebSocket handshake, RFC 6455 §10.2): only our own pages may.
  const auto origin = upgrade.headers.get("Origin");
  const auto host = upgrade.headers.get("Host");
  if (origin &&
      (!host || (*origin != "http://" + std::string(*host) && *origin != "https://" + std::string(*host)))) {
    return web::error_response(403, "cross-origin WebSocket refused");
  }
  if (session->role >= Role::viewer) {
    return web::TopicFilter([](std::string_view) { return true; });
  }
  return web::TopicFilter([this, user = session->user](std::string_view topic) {
    if (!topic.starts_with("order/")) {
      return false;
    }
    auto o = context.orders.find(std::string(topic.substr(6)));
    return o && o->owner == user;
  });
}

Result<std::unique_ptr<Dashboard>> Dashboard::create(cloud::Gateway& gateway, const line::Layout& layout,
                                                     DashboardConfig config, const Clock& clock) {
  if (config.users.empty()) {
    return make_error(Errc::invalid_argument,
                      "the dashboard needs a users file (smartfactory opcua users add)");
  }
  auto users = opcua::security::UsersFile::open(config.users);
  if (!users) {
    return Error(users.error()).with_context("web users");
  }
  // A session cookie sent over TLS must never travel in clear text (RFC 6265 §8.6).
  config.secure_cookies = config.secure_cookies || config.http.tls.has_value();
  auto impl = std::make_unique<Impl>(gateway, layout, std::move(config), clock, std::move(*users));
  return std::unique_ptr<Dashboard>(new Dashboard(std::move(impl)));
}

Dashboard::Dashboard(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}

Dashboard::~Dashboard() {
  stop();
}

Result<std::uint16_t> Dashboard::start() {
  Impl& m = *impl_;
  web::Router router;
  SF_TRY(add_session_routes(router, m.context));
  SF_TRY(add_order_routes(router, m.context));
  SF_TRY(add_machine_routes(router, m.context));
  SF_TRY(add_history_routes(router, m.context));
  web::ServerConfig http = m.context.config.http;
  http.live_access = [this](const web::Request& upgrade) { return impl_->live_access(upgrade); };
  m.replay();
  m.routes = router.routes();
  m.server = std::make_unique<web::HttpServer>(std::move(http), std::move(router));
  auto port = m.server->start();
  if (!port) {
    m.server.reset();
    return port.error();
  }
  m.context.set_server(m.server.get());
  // With the current values: machines that do not change are shown from the first request.
  m.subscription = m.context.gateway.live().subscribe_with_current(
      [this](const cloud::LiveUpdate& u) { impl_->on_value(u); },
      [this](const historian::Event& e) { impl_->on_event(e); });
  return port;
}

void Dashboard::stop() {
  Impl& m = *impl_;
  m.subscription = {};
  m.context.set_server(nullptr);
  if (m.server) {
    m.server->stop();
    m.server.reset();
  }
}

std::vector<std::pair<std::string, std::string>> Dashboard::routes() const {
  return impl_->routes;
}

DashboardStatus Dashboard::status() const {
  const Impl& m = *impl_;
  DashboardStatus s;
  s.orders = m.context.orders.size();
  s.sessions = m.context.sessions.size();
  s.rejected_events = m.context.orders.rejected();
  if (m.server) {
    s.http = m.server->stats();
  }
  return s;
}

}  // namespace sf::dashboard
