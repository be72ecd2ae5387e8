// History: the historian's series (raw and aggregated), the knowledge loop's alarms, OEE.
#include <charconv>

#include <fmt/format.h>

#include "context.hpp"
#include "json_values.hpp"
#include "sf/cloud/knowledge_loop.hpp"
#include "sf/dashboard/oee_history.hpp"
#include "sf/line/ontology.hpp"

namespace sf::dashboard {

namespace {

using web::Request;
using web::Response;

constexpr historian::Micros kDefaultRange = std::chrono::hours(1);
constexpr historian::Micros kLongestRange = std::chrono::hours(24 * 366);

// from/to of the query (openapi.yaml From, To): to defaults to now, from to an hour before it.
Result<TimeRange> range_of(const Context& c, const Request& r) {
  const auto now = c.now();
  TimeRange range{now - kDefaultRange, now};
  if (auto it = r.query_params.find("to"); it != r.query_params.end()) {
    auto to = parse_time_param(it->second, now);
    if (!to) {
      return Error(to.error()).with_context("to");
    }
    range = {*to - kDefaultRange, *to};
  }
  if (auto it = r.query_params.find("from"); it != r.query_params.end()) {
    auto from = parse_time_param(it->second, now);
    if (!from) {
      return Error(from.error()).with_context("from");
    }
    range.from = *from;
  }
  if (range.from >= range.to) {
    return make_error(Errc::invalid_argument, "from must be before to");
  }
  if (range.length() > kLongestRange) {
    return make_error(Errc::invalid_argument, "the range is longer than a year: narrow it");
  }
  return range;
}

Result<historian::Series> series_of(Context& c, const Request& r) {
  const std::string& text = r.path_params.at("id");
  historian::SeriesId id = 0;
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), id);
  if (error != std::errc{} || end != text.data() + text.size()) {
    return make_error(Errc::invalid_argument, fmt::format("series id '{}' is not a number", text));
  }
  return c.series(id);
}

Response store_error(const Error& e) {
  if (e.code == Errc::not_found) {
    return web::error_response(404, e.message);
  }
  if (e.code == Errc::invalid_argument || e.code == Errc::limit_exceeded || e.code == Errc::malformed) {
    return web::error_response(400, e.message);
  }
  return web::error_response(503, "the historian: " + e.message);
}

// The id as text: a 63-bit hash, which a JavaScript number (exact to 2^53) would round to another.
nlohmann::json series_json(const historian::Series& s) {
  return {{"id", std::to_string(s.id)},
          {"server", s.info.server},
          {"browse_path", s.info.browse_path},
          {"node_id", s.info.node_id},
          {"data_type", to_string(s.info.data_type)},
          {"unit", s.info.unit}};
}

Response list_series(Context& c, const Request& r) {
  auto all = c.gateway.store().list_series();
  if (!all) {
    return store_error(all.error());
  }
  const auto server = r.query_params.find("server");
  const auto path = r.query_params.find("path");
  nlohmann::json out = nlohmann::json::array();
  for (const auto& s : *all) {
    if ((server == r.query_params.end() || s.info.server == server->second) &&
        (path == r.query_params.end() || s.info.browse_path.starts_with(path->second))) {
      out.push_back(series_json(s));
    }
  }
  return web::json_response(out);
}

Response raw(Context& c, const Request& r) {
  auto series = series_of(c, r);
  auto range = range_of(c, r);
  auto limit = int_param(r, "limit", 10'000, 1, 100'000);
  if (!series || !range || !limit) {
    return store_error(!series ? series.error() : !range ? range.error() : limit.error());
  }
  auto samples =
      c.gateway.store().read_raw(series->id, range->from, range->to, static_cast<std::size_t>(*limit));
  if (!samples) {
    return store_error(samples.error());
  }
  nlohmann::json out = nlohmann::json::array();
  for (const auto& s : *samples) {
    out.push_back({{"t", time_text(s.source_time)}, {"v", value_json(s.value)}, {"status", s.status}});
  }
  return web::json_response(out);
}

Response aggregate(Context& c, const Request& r) {
  auto series = series_of(c, r);
  auto range = range_of(c, r);
  auto points = int_param(r, "points", 1000, 1, 10'000);
  if (!series || !range || !points) {
    return store_error(!series ? series.error() : !range ? range.error() : points.error());
  }
  const auto interval = std::max(historian::Micros{1}, range->length() / *points);
  auto rows =
      c.gateway.store().aggregate(series->id, range->from, range->to, interval, historian::Aggregate::all);
  if (!rows) {
    return store_error(rows.error());
  }
  nlohmann::json out = nlohmann::json::array();
  for (const auto& row : *rows) {
    auto number = [](const auto& v) { return v ? nlohmann::json(*v) : nlohmann::json(nullptr); };
    out.push_back({{"t", time_text(row.start)},
                   {"min", number(row.min)},
                   {"max", number(row.max)},
                   {"avg", number(row.avg)},
                   {"count", row.count.value_or(0)}});
  }
  return web::json_response(out);
}

// An operator's acknowledgement (OPC 10000-9 §5.7.3 Acknowledge): the knowledge loop records it
// (historian, OPC UA event); the alarm as it is then.
Response acknowledge(Context& c, const Request& r, const Session& s) {
  std::string comment;
  if (!r.body.empty()) {
    auto body = web::json_body(r);
    if (!body) {
      return web::error_response(400, body.error().message);
    }
    if (!body->is_object() || (body->contains("comment") && !(*body)["comment"].is_string())) {
      return web::error_response(400, R"(expected {"comment": "..."} or no body)");
    }
    comment = body->value("comment", "");
    if (comment.size() > 1000) {
      return web::error_response(400, "the comment is longer than 1000 characters");
    }
  }
  auto* k = c.gateway.knowledge();
  const std::string& id = r.path_params.at("id");
  if (k == nullptr) {
    return web::error_response(404, fmt::format("no alarm '{}' (the cloud runs no knowledge loop)", id));
  }
  if (auto acked = k->acknowledge(id, s.user, comment); !acked) {
    return web::error_response(acked.error().code == Errc::not_found ? 404 : 409, acked.error().message);
  }
  for (const auto& a : k->active_alarms()) {
    if (a.id == id) {
      return web::json_response(alarm_json(a));
    }
  }
  return web::json_response({{"id", id}, {"acked", true}, {"acked_by", s.user}});
}

// The alarms raised and cleared in a range, as the historian keeps them (cloud::alarm_event).
Response alarm_history(Context& c, const Request& r) {
  auto range = range_of(c, r);
  if (!range) {
    return store_error(range.error());
  }
  auto events =
      c.gateway.store().read_events({range->from, range->to, std::string(cloud::kKnowledgeServer), 10'000});
  if (!events) {
    return store_error(events.error());
  }
  nlohmann::json out = nlohmann::json::array();
  for (const auto& e : *events) {
    if (auto alarm = alarm_of(e)) {
      out.push_back(std::move(*alarm));
    }
  }
  return web::json_response(out);
}

Response alarms(Context& c, const Request& r) {
  const auto active = r.query_params.find("active");
  if (active != r.query_params.end() && active->second != "true" && active->second != "false") {
    return web::error_response(400, "active must be true or false");
  }
  if (active != r.query_params.end() && active->second == "false") {
    return alarm_history(c, r);
  }
  nlohmann::json out = nlohmann::json::array();
  if (const auto* k = c.gateway.knowledge()) {
    for (const auto& a : k->active_alarms()) {
      out.push_back(alarm_json(a));
    }
  }
  return web::json_response(out);
}

nlohmann::json oee_json(const std::string& machine, std::optional<double> a, std::optional<double> p,
                        std::optional<double> q, std::optional<double> oee) {
  auto number = [](std::optional<double> v) { return v ? nlohmann::json(*v) : nlohmann::json(nullptr); };
  return {{"machine", machine},
          {"availability", number(a)},
          {"performance", number(p)},
          {"quality", number(q)},
          {"oee", number(oee)}};
}

nlohmann::json machine_oee_json(const MachineOee& m) {
  auto j = oee_json(m.machine, m.availability, m.performance, m.quality, m.oee);
  j["produced"] = m.produced ? nlohmann::json(*m.produced) : nlohmann::json(nullptr);
  j["defective"] = m.defective ? nlohmann::json(*m.defective) : nlohmann::json(nullptr);
  j["no_data"] = m.no_data;
  j["from"] = time_text(m.range.from);
  j["to"] = time_text(m.range.to);
  return j;
}

Response oee(Context& c, const Request& r) {
  auto range = range_of(c, r);
  auto buckets = int_param(r, "buckets", 0, 0, 1000);
  if (!range || !buckets) {
    return store_error(!range ? range.error() : buckets.error());
  }
  range->to = std::min(range->to, c.now());  // the last state holds until `to`: not past now
  if (range->from >= range->to) {
    return web::error_response(400, "the range lies in the future");
  }
  const auto ideal = ideal_cycle_times(c.layout);
  std::vector<std::string> machines;
  if (auto it = r.query_params.find("machine"); it != r.query_params.end()) {
    machines.push_back(line::iri_name(it->second));
  }
  auto& store = c.gateway.store();
  auto line = line_oee(store, machines, *range, ideal);
  if (!line) {
    return store_error(line.error());
  }
  nlohmann::json out{{"machines", nlohmann::json::array()}};
  for (const auto& m : line->machines) {
    out["machines"].push_back(machine_oee_json(m));
  }
  out["line"] = oee_json(line->constraint.value_or(""), line->availability, line->performance, line->quality,
                         line->oee);
  if (*buckets > 0) {
    auto trend = line_oee_trend(store, machines, *range, range->length() / *buckets, ideal);
    if (!trend) {
      return store_error(trend.error());
    }
    nlohmann::json points = nlohmann::json::array();
    for (const auto& t : *trend) {
      auto j = oee_json(t.constraint.value_or(""), t.availability, t.performance, t.quality, t.oee);
      j["from"] = time_text(t.range.from);
      points.push_back(std::move(j));
    }
    out["trend"] = std::move(points);
  }
  return web::json_response(out);
}

}  // namespace

Status add_history_routes(web::Router& router, Context& c) {
  SF_TRY(router.add("GET", "/api/series", guarded(c, Role::viewer, [&c](const Request& r, const Session&) {
                      return list_series(c, r);
                    })));
  SF_TRY(router.add("GET", "/api/series/{id}/raw",
                    guarded(c, Role::viewer, [&c](const Request& r, const Session&) { return raw(c, r); })));
  SF_TRY(router.add(
      "GET", "/api/series/{id}/aggregate",
      guarded(c, Role::viewer, [&c](const Request& r, const Session&) { return aggregate(c, r); })));
  SF_TRY(router.add("GET", "/api/alarms", guarded(c, Role::viewer, [&c](const Request& r, const Session&) {
                      return alarms(c, r);
                    })));
  SF_TRY(router.add("POST", "/api/alarms/{id}/ack",
                    guarded(c, Role::operator_,
                            [&c](const Request& r, const Session& s) { return acknowledge(c, r, s); })));
  SF_TRY(router.add("GET", "/api/oee",
                    guarded(c, Role::viewer, [&c](const Request& r, const Session&) { return oee(c, r); })));
  return {};
}

}  // namespace sf::dashboard
