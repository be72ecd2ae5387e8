// Orders: placed through the order service's SubmitOrder (after the same checks the service
// makes), followed in the order book, withdrawn with CancelOrder.
#include <cctype>

#include <fmt/format.h>

#include "context.hpp"
#include "json_values.hpp"
#include "sf/core/log.hpp"
#include "sf/factory/order.hpp"
#include "sf/opcua/builtin_types.hpp"

namespace sf::dashboard {

namespace {

using web::Request;
using web::Response;

constexpr std::string_view kOrderService = "/Objects/OrderService";
constexpr std::size_t kMaxLimit = 1000;

// The steps that make up an order's Contract Net (announce/bid/award in "awarded"'s detail, the
// route and its transports, retries).
bool negotiation_step(std::string_view what) {
  return what == "awarded" || what == "routed" || what == "transported" || what == "retry" ||
         what == "remade" || what == "accepted";
}

nlohmann::json step_json(const OrderStepView& s) {
  return {{"time", time_text(s.time)},
          {"what", s.step.what},
          {"machine", s.step.machine},
          {"detail", s.step.detail}};
}

// A user name as part of an order id: ids have no spaces (sf/line/inspection.hpp).
std::string id_part(std::string_view user) {
  std::string out;
  for (char ch : user.substr(0, 32)) {
    out += std::isalnum(static_cast<unsigned char>(ch)) != 0 || ch == '-' || ch == '_' ? ch : '_';
  }
  return out;
}

// The order a request's body asks for, checked against the catalog as the order service checks
// it (factory::validate).
Result<factory::Order> order_of(const Request& r, const line::Catalog& catalog) {
  auto body = web::json_body(r);
  if (!body) {
    return body.error();
  }
  if (!body->is_object() || !body->contains("box") || !(*body)["box"].is_string() ||
      !body->contains("candy") || !(*body)["candy"].is_object()) {
    return make_error(Errc::invalid_argument,
                      R"(expected {"box": "<box type>", "candy": {"<candy type>": <quantity>}})");
  }
  factory::Order order;
  order.box_type = (*body)["box"];
  for (const auto& [candy, quantity] : (*body)["candy"].items()) {
    if (!quantity.is_number_integer()) {
      return make_error(Errc::invalid_argument,
                        fmt::format("candy '{}': the quantity must be a whole number", candy));
    }
    const auto q = quantity.get<std::int64_t>();
    if (q < 1 || q > 10'000) {
      return make_error(Errc::invalid_argument,
                        fmt::format("candy '{}': quantity {} is not 1 or more", candy, q));
    }
    order.lines.push_back({candy, static_cast<int>(q)});
  }
  if (auto valid = factory::validate(order, catalog); !valid) {
    return valid.error();
  }
  return order;
}

// Consumers see their own orders only; an order of someone else is "not found" to them.
std::optional<OrderView> visible(Context& c, const std::string& id, const Session& s) {
  auto o = c.orders.find(id);
  if (!o || (s.role < Role::viewer && o->owner != s.user)) {
    return std::nullopt;
  }
  return o;
}

Response list(Context& c, const Request& r, const Session& s) {
  const auto limit = int_param(r, "limit", 100, 1, static_cast<std::int64_t>(kMaxLimit));
  if (!limit) {
    return web::error_response(400, limit.error().message);
  }
  std::optional<std::string> state;
  if (auto it = r.query_params.find("state"); it != r.query_params.end()) {
    state = it->second;
  }
  const auto owner = s.role < Role::viewer ? std::optional(s.user) : std::nullopt;
  nlohmann::json out = nlohmann::json::array();
  for (const auto& o : c.orders.list(owner, state, static_cast<std::size_t>(*limit))) {
    out.push_back(order_json(o));
  }
  return web::json_response(out);
}

Response place(Context& c, const Request& r, const Session& s) {
  auto order = order_of(r, c.layout.catalog);
  if (!order) {
    return web::error_response(400, order.error().message);
  }
  if (auto wait = c.order_limit.take(s.user)) {
    auto refused = web::error_response(429, "too many orders; try again later");
    refused.headers.set("Retry-After", std::to_string(wait->count()));
    return refused;
  }
  const auto server = c.order_server();
  if (!server) {
    return web::error_response(503, "the order service is not connected");
  }
  const auto now = c.now();
  order->id = fmt::format("{}-{:x}", id_part(s.user), historian::to_micros(now));
  std::vector<opcua::String> candy;
  for (const auto& l : order->lines) {
    candy.emplace_back(fmt::format("{}:{}", l.candy, l.quantity));
  }
  auto accepted =
      c.gateway.call(*server, std::string(kOrderService), "SubmitOrder",
                     {opcua::Variant(order->id), opcua::Variant(order->box_type), opcua::Variant(candy)});
  if (!accepted) {
    return call_error(accepted.error(), "the order service");
  }
  // Who placed it, kept where the order's steps are: the book is rebuilt from the historian.
  historian::Event owner;
  owner.server = std::string(kDashboardServer);
  owner.event_id = Bytes(order->id.begin(), order->id.end());
  owner.time = now;
  owner.receive_time = now;
  owner.event_type = "OrderPlaced";
  owner.source_name = order->id;
  owner.message = s.user;
  owner.severity = 100;
  if (auto stored = c.gateway.store().append_events({&owner, 1}); !stored) {
    log::get("dashboard")
        ->warn("order {}: its owner was not stored: {}", order->id, stored.error().describe());
  }
  c.orders.placed(order->id, s.user, order->box_type, order->counts(), now);
  auto response = web::json_response(order_json(*c.orders.find(order->id)), 201);
  response.headers.set("Location", "/api/orders/" + order->id);
  return response;
}

Response cancel(Context& c, const Request& r, const Session& s) {
  const std::string& id = r.path_params.at("id");
  auto o = visible(c, id, s);
  if (!o || (s.role < Role::operator_ && o->owner != s.user)) {
    return web::error_response(404, fmt::format("no order '{}'", id));
  }
  if (o->state != "queued" && o->state != "submitted") {
    return web::error_response(
        409, fmt::format("order '{}' is {}: only a queued order can be cancelled", id, o->state));
  }
  const auto server = c.order_server();
  if (!server) {
    return web::error_response(503, "the order service is not connected");
  }
  auto taken = c.gateway.call(*server, std::string(kOrderService), "CancelOrder", {opcua::Variant(id)});
  if (!taken) {
    return call_error(taken.error(), "the order service");
  }
  return web::json_response({{"id", id}, {"cancel", "requested"}}, 202);
}

}  // namespace

nlohmann::json order_json(const OrderView& o) {
  nlohmann::json steps = nlohmann::json::array();
  for (const auto& s : o.steps) {
    steps.push_back(step_json(s));
  }
  nlohmann::json out{{"id", o.id},
                     {"owner", o.owner},
                     {"box", o.box},
                     {"candy", o.candy},
                     {"state", o.state},
                     {"attempts", o.attempts},
                     {"machines", o.machines},
                     {"steps", std::move(steps)},
                     {"updated", time_text(o.updated)}};
  if (o.place) {
    nlohmann::json route = nlohmann::json::array();
    for (const auto& leg : o.place->route) {
      route.push_back({{"conveyor", leg.conveyor}, {"to", leg.to}});
    }
    out["place"] = {{"box", o.place->box}, {"at", o.place->at}, {"route", std::move(route)}};
  }
  if (o.inspection) {
    const auto& i = *o.inspection;
    out["inspection"] = {{"box", i.box},           {"ordered", i.ordered}, {"counted", i.counted},
                         {"weight_g", i.weight_g}, {"lead_s", i.lead_s},   {"matches", i.matches()}};
  }
  return out;
}

web::Response call_error(const Error& error, std::string_view what) {
  // The server's answer first (its StatusCode, OPC 10000-4 §7.39), then the connection's state.
  const auto says = [&](std::string_view code) { return error.message.find(code) != std::string::npos; };
  if (says("BadInvalidState")) {
    return web::error_response(409, fmt::format("{} refused: {}", what, error.message));
  }
  if (says("BadNotFound") || says("BadNodeIdUnknown") || says("BadMethodInvalid")) {
    return web::error_response(404, fmt::format("{}: {}", what, error.message));
  }
  if (says("BadInvalidArgument")) {
    return web::error_response(400, fmt::format("{} refused: {}", what, error.message));
  }
  if (says("BadUserAccessDenied")) {
    return web::error_response(502, fmt::format("{} refused the cloud's user: {}", what, error.message));
  }
  if (error.code == Errc::not_found) {
    return web::error_response(404, fmt::format("{}: {}", what, error.message));
  }
  if (error.code == Errc::state || error.code == Errc::io || error.code == Errc::timeout) {
    return web::error_response(503, fmt::format("{} is not reachable: {}", what, error.message));
  }
  return web::error_response(502, fmt::format("{}: {}", what, error.message));
}

Status add_order_routes(web::Router& router, Context& c) {
  SF_TRY(router.add(
      "GET", "/api/orders",
      guarded(c, Role::consumer, [&c](const Request& r, const Session& s) { return list(c, r, s); })));
  SF_TRY(router.add(
      "POST", "/api/orders",
      guarded(c, Role::consumer, [&c](const Request& r, const Session& s) { return place(c, r, s); })));
  SF_TRY(router.add(
      "GET", "/api/orders/{id}", guarded(c, Role::consumer, [&c](const Request& r, const Session& s) {
        auto o = visible(c, r.path_params.at("id"), s);
        return o ? web::json_response(order_json(*o))
                 : web::error_response(404, fmt::format("no order '{}'", r.path_params.at("id")));
      })));
  SF_TRY(router.add(
      "DELETE", "/api/orders/{id}",
      guarded(c, Role::consumer, [&c](const Request& r, const Session& s) { return cancel(c, r, s); })));
  SF_TRY(router.add("GET", "/api/orders/{id}/negotiation",
                    guarded(c, Role::consumer, [&c](const Request& r, const Session& s) {
                      auto o = visible(c, r.path_params.at("id"), s);
                      if (!o) {
                        return web::error_response(404, fmt::format("no order '{}'", r.path_params.at("id")));
                      }
                      nlohmann::json out = nlohmann::json::array();
                      for (const auto& step : o->steps) {
                        if (negotiation_step(step.step.what)) {
                          out.push_back(step_json(step));
                        }
                      }
                      return web::json_response(out);
                    })));
  return {};
}

}  // namespace sf::dashboard
