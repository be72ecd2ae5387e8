// `smartfactory history query|series|events|retention|write`: the historian's
// stores (paper §V.B: historical data and events in the cloud's database),
// SQLite or PostgreSQL by URL. Everything here parses options and prints;
// the historian module does the work.
#include <iostream>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "commands.hpp"
#include "history_common.hpp"
#include "sf/historian/store.hpp"
#include "sf/historian/time_text.hpp"

namespace sf::app {
namespace {

namespace hist = sf::historian;
using history_cli::add_db_option;
using history_cli::fail;
using history_cli::kTimeHelp;
using history_cli::now;
using history_cli::open_db;
using history_cli::series_json;
using history_cli::status_text;
using history_cli::value_json;
using nlohmann::json;

// --- history query ---------------------------------------------------------------

struct QueryOptions {
  std::string db;
  std::string series;
  std::string server;
  std::string from = "-1h";
  std::string to = "now";
  std::string aggregate;
  std::size_t limit = 10'000;
  bool json = false;
};

// A series by browse path, node id or numeric id; --server narrows it down.
Result<hist::Series> find_series(hist::Store& store, const QueryOptions& o) {
  auto all = store.list_series();
  if (!all) {
    return all.error();
  }
  std::vector<hist::Series> hits;
  for (const auto& s : *all) {
    const bool named =
        s.info.browse_path == o.series || s.info.node_id == o.series || std::to_string(s.id) == o.series;
    if (named && (o.server.empty() || s.info.server == o.server)) {
      hits.push_back(s);
    }
  }
  if (hits.empty()) {
    return make_error(Errc::not_found,
                      fmt::format("no series '{}'{} (list them: smartfactory history series --db "
                                  "URL)",
                                  o.series, o.server.empty() ? "" : " on " + o.server));
  }
  if (hits.size() > 1) {
    std::string servers;
    for (const auto& h : hits) {
      servers += "\n  " + h.info.server;
    }
    return make_error(Errc::invalid_argument, fmt::format("'{}' names {} series; choose one with --server:{}",
                                                          o.series, hits.size(), servers));
  }
  return hits.front();
}

struct AggregateSpec {
  hist::Aggregate which{};
  hist::Micros interval{};
};

// "avg:1s", "min,max:10m", "all:1h".
Result<AggregateSpec> parse_aggregate(const std::string& text) {
  const auto colon = text.rfind(':');
  if (colon == std::string::npos) {
    return make_error(
        Errc::invalid_argument,
        fmt::format("--aggregate {}: expected KINDS:INTERVAL like avg:1s or min,max:10m", text));
  }
  auto interval = hist::parse_duration(text.substr(colon + 1));
  if (!interval) {
    return interval.error();
  }
  if (interval->count() <= 0) {
    return make_error(Errc::invalid_argument, "--aggregate: the interval must be positive");
  }
  AggregateSpec spec{hist::Aggregate{}, *interval};
  std::string_view kinds = std::string_view{text}.substr(0, colon);
  while (!kinds.empty()) {
    const auto comma = kinds.find(',');
    const auto kind = kinds.substr(0, comma);
    const std::pair<std::string_view, hist::Aggregate> names[] = {{"min", hist::Aggregate::min},
                                                                  {"max", hist::Aggregate::max},
                                                                  {"avg", hist::Aggregate::avg},
                                                                  {"count", hist::Aggregate::count},
                                                                  {"all", hist::Aggregate::all}};
    bool known = false;
    for (const auto& [name, a] : names) {
      if (kind == name) {
        spec.which = spec.which | a;
        known = true;
      }
    }
    if (!known) {
      return make_error(Errc::invalid_argument,
                        fmt::format("--aggregate: unknown aggregate '{}' (min, max, avg, count, all)", kind));
    }
    kinds = comma == std::string_view::npos ? std::string_view{} : kinds.substr(comma + 1);
  }
  return spec;
}

std::string opt_number(const std::optional<double>& v) {
  return v ? fmt::format("{}", *v) : "-";
}

int print_aggregates(const hist::Series& s, const std::vector<hist::AggregateRow>& rows, bool as_json) {
  if (as_json) {
    json out = json::array();
    for (const auto& r : rows) {
      json row{{"start", hist::format_time(r.start)}};
      if (r.count) {
        row["count"] = *r.count;
      }
      for (const auto& [name, v] :
           {std::pair{"min", r.min}, std::pair{"max", r.max}, std::pair{"avg", r.avg}}) {
        if (v) {
          row[name] = *v;
        }
      }
      out.push_back(row);
    }
    std::cout << json{{"series", series_json(s)}, {"aggregates", out}}.dump(2) << "\n";
    return kExitOk;
  }
  std::cout << fmt::format("{:<28} {:>8} {:>14} {:>14} {:>14}\n", "interval start", "count", "min", "max",
                           "avg");
  for (const auto& r : rows) {
    std::cout << fmt::format("{:<28} {:>8} {:>14} {:>14} {:>14}\n", hist::format_time(r.start),
                             r.count ? std::to_string(*r.count) : "-", opt_number(r.min), opt_number(r.max),
                             opt_number(r.avg));
  }
  return kExitOk;
}

int print_samples(const hist::Series& s, const std::vector<hist::Sample>& rows, bool as_json) {
  if (as_json) {
    json out = json::array();
    for (const auto& r : rows) {
      out.push_back(json{{"source_time", hist::format_time(r.source_time)},
                         {"server_time", hist::format_time(r.server_time)},
                         {"seq", r.seq},
                         {"type", std::string{hist::to_string(hist::type_of(r.value))}},
                         {"value", value_json(r.value)},
                         {"status", r.status}});
    }
    std::cout << json{{"series", series_json(s)}, {"samples", out}}.dump(2) << "\n";
    return kExitOk;
  }
  std::cout << fmt::format("{:<28} {:>20}  {}\n", "source time", "value", "status");
  for (const auto& r : rows) {
    std::cout << fmt::format("{:<28} {:>20}  {}\n", hist::format_time(r.source_time),
                             hist::format_value(r.value), status_text(r.status));
  }
  return kExitOk;
}

int run_query(const QueryOptions& o) {
  const auto t = now();
  auto from = hist::parse_time(o.from, t);
  auto to = hist::parse_time(o.to, t);
  if (!from || !to) {
    return fail(from ? to.error() : from.error());
  }
  std::optional<AggregateSpec> spec;
  if (!o.aggregate.empty()) {
    auto parsed = parse_aggregate(o.aggregate);
    if (!parsed) {
      return fail(parsed.error());
    }
    spec = *parsed;
  }
  auto store = open_db(o.db);
  if (!store) {
    return fail(store.error());
  }
  auto series = find_series(**store, o);
  if (!series) {
    return fail(series.error());
  }
  std::cerr << fmt::format("history: {} ({} on {}) from {} to {}\n", series->info.browse_path,
                           series->info.node_id, series->info.server, hist::format_time(*from),
                           hist::format_time(*to));
  if (spec) {
    auto rows = (*store)->aggregate(series->id, *from, *to, spec->interval, spec->which);
    return rows ? print_aggregates(*series, *rows, o.json) : fail(rows.error());
  }
  auto rows = (*store)->read_raw(series->id, *from, *to, o.limit);
  if (!rows) {
    return fail(rows.error());
  }
  if (rows->size() == o.limit) {
    std::cerr << fmt::format("history: stopped at --limit {}; more samples may follow\n", o.limit);
  }
  return print_samples(*series, *rows, o.json);
}

void register_query(CLI::App& history, CommandResult& result) {
  auto o = std::make_shared<QueryOptions>();
  auto* cmd = history.add_subcommand(
      "query", "Samples of one series in a time range: raw, or aggregated per interval");
  add_db_option(*cmd, o->db);
  cmd->add_option("--series", o->series, "The series: its browse path, node id or numeric id")->required();
  cmd->add_option("--server", o->server, "The server the series belongs to, when the name is not unique");
  cmd->add_option("--from", o->from, std::string{"Start of the range (inclusive); "} + kTimeHelp)
      ->capture_default_str();
  cmd->add_option("--to", o->to, std::string{"End of the range (exclusive); "} + kTimeHelp)
      ->capture_default_str();
  cmd->add_option(
      "--aggregate", o->aggregate,
      "Aggregates per interval instead of raw samples: KINDS:INTERVAL, kinds min,max,avg,count or all, "
      "e.g. avg:1s, min,max:10m, all:1h (Bad samples are left out)");
  cmd->add_option("--limit", o->limit, "At most this many raw samples")->capture_default_str();
  cmd->add_flag("--json", o->json, "Print the result as JSON on stdout");
  cmd->callback([o, &result] { result.exit_code = run_query(*o); });
}

// --- history series ----------------------------------------------------------------

struct ListOptions {
  std::string db;
  bool json = false;
};

int run_series(const ListOptions& o) {
  auto store = open_db(o.db);
  if (!store) {
    return fail(store.error());
  }
  auto all = (*store)->list_series();
  if (!all) {
    return fail(all.error());
  }
  if (o.json) {
    json out = json::array();
    for (const auto& s : *all) {
      out.push_back(series_json(s));
    }
    std::cout << out.dump(2) << "\n";
    return kExitOk;
  }
  std::cout << fmt::format("{:<40} {:<8} {:<6} {:<28} {}\n", "browse path", "type", "unit", "node id",
                           "server");
  for (const auto& s : *all) {
    std::cout << fmt::format("{:<40} {:<8} {:<6} {:<28} {}\n", s.info.browse_path,
                             hist::to_string(s.info.data_type), s.info.unit, s.info.node_id, s.info.server);
  }
  std::cerr << fmt::format("history: {} series\n", all->size());
  return kExitOk;
}

void register_series(CLI::App& history, CommandResult& result) {
  auto o = std::make_shared<ListOptions>();
  auto* cmd =
      history.add_subcommand("series", "List the series registry (server, node id, browse path, type, unit)");
  add_db_option(*cmd, o->db);
  cmd->add_flag("--json", o->json, "Print the registry as JSON on stdout");
  cmd->callback([o, &result] { result.exit_code = run_series(*o); });
}

// --- history retention --------------------------------------------------------------

struct RetentionOptions {
  std::string db;
  std::string keep;
  bool json = false;
};

int run_retention(const RetentionOptions& o) {
  auto keep = hist::parse_duration(o.keep);
  if (!keep) {
    return fail(keep.error());
  }
  auto store = open_db(o.db);
  if (!store) {
    return fail(store.error());
  }
  const auto before = now() - *keep;
  auto done = (*store)->apply_retention(before);
  if (!done) {
    return fail(done.error());
  }
  if (o.json) {
    std::cout << json{{"before", hist::format_time(before)},
                      {"samples_deleted", done->samples_deleted},
                      {"events_deleted", done->events_deleted},
                      {"partitions_dropped", done->partitions_dropped}}
                     .dump(2)
              << "\n";
  } else {
    std::cout << fmt::format(
        "kept data from {} on: {} samples and {} events deleted, {} partitions dropped\n",
        hist::format_time(before), done->samples_deleted, done->events_deleted, done->partitions_dropped);
  }
  return kExitOk;
}

void register_retention(CLI::App& history, CommandResult& result) {
  auto o = std::make_shared<RetentionOptions>();
  auto* cmd = history.add_subcommand("retention", "Delete samples and events older than --keep");
  add_db_option(*cmd, o->db);
  cmd->add_option("--keep", o->keep, "How much history to keep, e.g. 7d, 12h, 2w")->required();
  cmd->add_flag("--json", o->json, "Print what was deleted as JSON on stdout");
  cmd->callback([o, &result] { result.exit_code = run_retention(*o); });
}

}  // namespace

void register_history(CLI::App& app, CommandResult& result) {
  auto* history = app.add_subcommand(
      "history", "Historian: the store of historical data and events (SQLite or PostgreSQL, chosen by URL)");
  history->require_subcommand(1);
  register_query(*history, result);
  register_series(*history, result);
  history_cli::register_events(*history, result);
  register_retention(*history, result);
  history_cli::register_write(*history, result);
}

}  // namespace sf::app
