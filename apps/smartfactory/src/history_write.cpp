// `smartfactory history events` (read events) and `history write` (one sample
// by hand: for scripts, tests and readings taken on paper).
#include <charconv>
#include <iostream>
#include <memory>
#include <string>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "commands.hpp"
#include "history_common.hpp"
#include "sf/historian/time_text.hpp"

namespace sf::app {
namespace {

namespace hist = sf::historian;
using history_cli::fail;
using history_cli::now;
using history_cli::open_db;
using nlohmann::json;

// --- history events ------------------------------------------------------------------

struct EventsOptions {
  std::string db;
  std::string server;
  std::string from = "-1h";
  std::string to = "now";
  std::size_t limit = 10'000;
  bool json = false;
};

int run_events(const EventsOptions& o) {
  const auto t = now();
  auto from = hist::parse_time(o.from, t);
  auto to = hist::parse_time(o.to, t);
  if (!from || !to) {
    return fail(from ? to.error() : from.error());
  }
  auto store = open_db(o.db);
  if (!store) {
    return fail(store.error());
  }
  hist::EventQuery query{.from = *from, .to = *to, .limit = o.limit};
  if (!o.server.empty()) {
    query.server = o.server;
  }
  auto events = (*store)->read_events(query);
  if (!events) {
    return fail(events.error());
  }
  if (o.json) {
    json out = json::array();
    for (const auto& e : *events) {
      out.push_back(json{{"time", hist::format_time(e.time)},
                         {"receive_time", hist::format_time(e.receive_time)},
                         {"server", e.server},
                         {"event_id", hist::format_value(hist::Value{e.event_id})},
                         {"event_type", e.event_type},
                         {"source_node", e.source_node},
                         {"source_name", e.source_name},
                         {"severity", e.severity},
                         {"message", e.message},
                         {"fields", e.fields}});
    }
    std::cout << out.dump(2) << "\n";
    return kExitOk;
  }
  for (const auto& e : *events) {
    std::cout << fmt::format("{}  {:>4}  {:<20} {}\n", hist::format_time(e.time), e.severity, e.source_name,
                             e.message);
  }
  std::cerr << fmt::format("history: {} events\n", events->size());
  return kExitOk;
}

}  // namespace

void history_cli::register_events(CLI::App& history, CommandResult& result) {
  auto o = std::make_shared<EventsOptions>();
  auto* cmd = history.add_subcommand("events", "Events in a time range, oldest first");
  add_db_option(*cmd, o->db);
  cmd->add_option("--server", o->server, "Only events of this server (endpoint URL or ApplicationUri)");
  cmd->add_option("--from", o->from, std::string{"Start of the range (inclusive); "} + kTimeHelp)
      ->capture_default_str();
  cmd->add_option("--to", o->to, std::string{"End of the range (exclusive); "} + kTimeHelp)
      ->capture_default_str();
  cmd->add_option("--limit", o->limit, "At most this many events")->capture_default_str();
  cmd->add_flag("--json", o->json, "Print the events as JSON on stdout");
  cmd->callback([o, &result] { result.exit_code = run_events(*o); });
}

// --- history write ---------------------------------------------------------------------

namespace {

struct HistoryWriteOptions {
  std::string db;
  hist::SeriesInfo series{.server = "manual"};
  std::string type = "float64";
  std::string value;
  std::string time = "now";
  std::uint32_t status = hist::kGood;
  std::uint32_t seq = 0;
  bool json = false;
};

template <typename T>
Result<hist::Value> number(const std::string& text) {
  T v{};
  const auto [p, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
  if (ec != std::errc{} || p != text.data() + text.size()) {
    return make_error(Errc::invalid_argument, fmt::format("--value '{}' is not a number of that type", text));
  }
  return hist::Value{v};
}

Result<hist::Value> parse_value(hist::DataType type, const std::string& text) {
  switch (type) {
    case hist::DataType::empty:
      return hist::Value{};
    case hist::DataType::boolean:
      if (text == "true" || text == "false") {
        return hist::Value{text == "true"};
      }
      return make_error(Errc::invalid_argument, "--value of a boolean: true or false");
    case hist::DataType::int64:
      return number<std::int64_t>(text);
    case hist::DataType::uint64:
      return number<std::uint64_t>(text);
    case hist::DataType::float64:
      return number<double>(text);
    case hist::DataType::string:
      return hist::Value{text};
    case hist::DataType::bytes: {
      auto bytes = from_hex(text);
      return bytes ? Result<hist::Value>{hist::Value{*bytes}} : Result<hist::Value>{bytes.error()};
    }
  }
  return make_error(Errc::invalid_argument, "unknown type");
}

int run_history_write(HistoryWriteOptions o) {
  const auto type = hist::data_type_from_string(o.type);
  if (!type) {
    return fail(make_error(
        Errc::invalid_argument,
        fmt::format("--type {}: boolean, int64, uint64, float64, string, bytes or empty", o.type)));
  }
  o.series.data_type = *type;
  auto value = parse_value(*type, o.value);
  auto at = hist::parse_time(o.time, now());
  if (!value || !at) {
    return fail(value ? at.error() : value.error());
  }
  auto store = open_db(o.db);
  if (!store) {
    return fail(store.error());
  }
  auto id = (*store)->register_series(o.series);
  if (!id) {
    return fail(id.error());
  }
  const hist::Sample sample{*id, *at, now(), o.seq, o.status, *value};
  if (auto st = (*store)->append({&sample, 1}); !st) {
    return fail(st.error());
  }
  if (o.json) {
    std::cout << json{{"series", *id}, {"source_time", hist::format_time(*at)}}.dump() << "\n";
  } else {
    std::cout << fmt::format("{} = {} at {} (series {})\n", o.series.browse_path, hist::format_value(*value),
                             hist::format_time(*at), *id);
  }
  return kExitOk;
}

}  // namespace

void history_cli::register_write(CLI::App& history, CommandResult& result) {
  auto o = std::make_shared<HistoryWriteOptions>();
  auto* cmd = history.add_subcommand("write", "Write one sample, registering its series if needed");
  add_db_option(*cmd, o->db);
  cmd->add_option("--server", o->series.server, "Server of the series (endpoint URL or ApplicationUri)")
      ->capture_default_str();
  cmd->add_option("--node", o->series.node_id, "Node id of the series, e.g. ns=2;s=Line1.Temp")->required();
  cmd->add_option("--path", o->series.browse_path,
                  "Browse path, e.g. /Objects/Line1/Temp (what queries name)");
  cmd->add_option("--unit", o->series.unit, "Engineering unit, e.g. degC");
  cmd->add_option("--type", o->type,
                  "Value type: boolean, int64, uint64, float64, string, bytes (hex), empty")
      ->capture_default_str();
  cmd->add_option("--value", o->value, "The value, in the notation of its type")->required();
  cmd->add_option("--time", o->time, std::string{"Source timestamp; "} + kTimeHelp)->capture_default_str();
  cmd->add_option("--status", o->status, "OPC UA StatusCode (0 = Good)")->capture_default_str();
  cmd->add_option("--seq", o->seq, "Tells apart samples with the same source timestamp")
      ->capture_default_str();
  cmd->add_flag("--json", o->json, "Print the series id and time as JSON on stdout");
  cmd->callback([o, &result] { result.exit_code = run_history_write(*o); });
}

}  // namespace sf::app
