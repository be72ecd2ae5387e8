// Sessions, the catalog, the layout, status and the API description (openapi.yaml).
#include <fmt/format.h>

#include "context.hpp"
#include "sf/line/layout.hpp"

namespace sf::dashboard {

namespace {

using web::Request;
using web::Response;

nlohmann::json session_json(const Session& s) {
  return {{"user", s.user}, {"role", to_string(s.role)}, {"csrf", s.csrf}};
}

Response login(Context& c, const Request& r) {
  auto body = web::json_body(r);
  if (!body) {
    return web::error_response(400, body.error().message);
  }
  if (!body->is_object() || !body->contains("user") || !body->contains("password") ||
      !(*body)["user"].is_string() || !(*body)["password"].is_string()) {
    return web::error_response(400, R"(expected {"user": "...", "password": "..."})");
  }
  const std::string user = (*body)["user"];
  if (auto wait = c.login_limit.take(user)) {
    auto refused = web::error_response(429, "too many logins for this user; try again later");
    refused.headers.set("Retry-After", std::to_string(wait->count()));
    return refused;
  }
  auto session = c.sessions.login(user, (*body)["password"].get<std::string>());
  if (!session) {
    return web::error_response(session.error().code == Errc::state ? 403 : 401, session.error().message);
  }
  auto response = web::json_response(session_json(*session));
  response.headers.set("Set-Cookie", Sessions::cookie(session->id, c.config.secure_cookies));
  response.headers.set("Cache-Control", "no-store");
  return response;
}

nlohmann::json catalog_json(const line::Catalog& catalog) {
  nlohmann::json boxes = nlohmann::json::array();
  for (const auto& b : catalog.box_types) {
    boxes.push_back({{"name", b.name}, {"label", b.label}, {"capacity", b.capacity()}});
  }
  nlohmann::json candy = nlohmann::json::array();
  for (const auto& t : catalog.candy_types) {
    candy.push_back({{"name", t.name}, {"label", t.label}});
  }
  return {{"box_types", std::move(boxes)}, {"candy_types", std::move(candy)}};
}

nlohmann::json point(const motion::Vec2& p) {
  return {p.x, p.y};
}

// What the operator's schematic draws: belts as polylines with their stations, robots and
// transfers at their stations, dispensers.
nlohmann::json layout_json(const line::Layout& l) {
  nlohmann::json belts = nlohmann::json::array();
  for (const auto& b : l.belts) {
    nlohmann::json path = nlohmann::json::array();
    for (const auto& p : b.path) {
      path.push_back(point(p));
    }
    nlohmann::json stations = nlohmann::json::array();
    for (const auto& s : b.stations) {
      stations.push_back({{"name", s.name}, {"at_m", s.at_m}, {"point", point(b.point_at(s.at_m))}});
    }
    belts.push_back({{"name", b.name},
                     {"label", b.label},
                     {"path", std::move(path)},
                     {"next", b.next},
                     {"stations", std::move(stations)}});
  }
  nlohmann::json machines = nlohmann::json::array();
  for (const auto& r : l.robots) {
    machines.push_back({{"name", r.name},
                        {"label", r.label},
                        {"kind", to_string(r.kind)},
                        {"stations", r.stations},
                        {"dispensers", r.dispensers}});
  }
  for (const auto* t : {&l.uploader, &l.downloader}) {
    machines.push_back({{"name", t->name},
                        {"label", t->label},
                        {"kind", t == &l.uploader ? "uploader" : "downloader"},
                        {"stations", {t->station}}});
  }
  nlohmann::json dispensers = nlohmann::json::array();
  for (const auto& d : l.dispensers) {
    dispensers.push_back({{"name", d.name}, {"candy", d.candy}, {"point", {d.at.x, d.at.y}}});
  }
  return {{"line", l.line},
          {"label", l.label},
          {"belts", std::move(belts)},
          {"machines", std::move(machines)},
          {"dispensers", std::move(dispensers)}};
}

nlohmann::json status_json(Context& c) {
  const auto g = c.gateway.status();
  nlohmann::json servers = nlohmann::json::array();
  for (const auto& s : g.servers) {
    c.machines.set_connected(s.name, s.connected);
    servers.push_back({{"name", s.name},
                       {"phase", s.phase},
                       {"connected", s.connected},
                       {"series", s.series},
                       {"samples", s.samples},
                       {"events", s.events},
                       {"last_error", s.last_error}});
  }
  nlohmann::json out{{"servers", std::move(servers)},      {"samples_written", g.samples_written},
                     {"events_written", g.events_written}, {"queued", g.queued},
                     {"orders", c.orders.size()},          {"sessions", c.sessions.size()}};
  if (const auto* k = c.gateway.knowledge()) {
    const auto ks = k->status();
    out["knowledge"] = {{"values", ks.values}, {"active_alarms", ks.active_alarms}, {"triples", ks.triples}};
  }
  return out;
}

}  // namespace

Status add_session_routes(web::Router& router, Context& c) {
  SF_TRY(router.add("POST", "/api/session", [&c](const Request& r) { return login(c, r); }));
  SF_TRY(router.add("GET", "/api/session", guarded(c, Role::consumer, [](const Request&, const Session& s) {
                      return web::json_response(session_json(s));
                    })));
  SF_TRY(
      router.add("DELETE", "/api/session", guarded(c, Role::consumer, [&c](const Request&, const Session& s) {
                   c.sessions.logout(s.id);
                   Response out;
                   out.status = 204;
                   out.headers.set("Set-Cookie", Sessions::cookie({}, c.config.secure_cookies));
                   return out;
                 })));
  SF_TRY(router.add("GET", "/api/catalog",
                    [&c](const Request&) { return web::json_response(catalog_json(c.layout.catalog)); }));
  SF_TRY(router.add("GET", "/api/layout", guarded(c, Role::viewer, [&c](const Request&, const Session&) {
                      return web::json_response(layout_json(c.layout));
                    })));
  SF_TRY(router.add("GET", "/api/status", guarded(c, Role::viewer, [&c](const Request&, const Session&) {
                      return web::json_response(status_json(c));
                    })));
  SF_TRY(router.add("GET", "/api/openapi.yaml", [](const Request&) {
    Response out;
    out.content_type = "application/yaml";
    out.body = std::string(openapi_yaml());
    return out;
  }));
  return {};
}

}  // namespace sf::dashboard
