#include "history_common.hpp"

#include <iostream>

#include <fmt/format.h>

#include "commands.hpp"
#include "sf/core/clock.hpp"

namespace sf::app::history_cli {

namespace hist = sf::historian;
using nlohmann::json;

void add_db_option(CLI::App& cmd, std::string& db) {
  cmd.add_option("--db", db,
                 "Store URL: sqlite:PATH (e.g. sqlite:/var/lib/smartfactory/history.db) or "
                 "postgresql://user@host:port/database")
      ->required()
      ->envname("SF_HISTORY_DB");
}

Result<std::unique_ptr<hist::Store>> open_db(const std::string& url) {
  return hist::open_store(url);
}

hist::Timestamp now() {
  return std::chrono::time_point_cast<hist::Micros>(SteadyClock::instance().utc_now());
}

int fail(const Error& e) {
  std::cerr << "history: " << e.describe() << "\n";
  return e.code == Errc::invalid_argument || e.code == Errc::not_found ? kExitUsage : kExitFailure;
}

std::string status_text(hist::StatusCode s) {
  if (s == hist::kGood) {
    return "Good";
  }
  const char* severity = hist::is_bad(s) ? "Bad" : (s >> 30U) == 1U ? "Uncertain" : "Good";
  return fmt::format("{} (0x{:08X})", severity, s);
}

json value_json(const hist::Value& v) {
  switch (hist::type_of(v)) {
    case hist::DataType::empty:
      return nullptr;
    case hist::DataType::boolean:
      return std::get<bool>(v);
    case hist::DataType::int64:
      return std::get<std::int64_t>(v);
    case hist::DataType::uint64:
      return std::get<std::uint64_t>(v);
    case hist::DataType::float64:
      return std::get<double>(v);
    case hist::DataType::string:
      return std::get<std::string>(v);
    case hist::DataType::bytes:
      return hist::format_value(v);  // "0x..."
  }
  return nullptr;
}

json series_json(const hist::Series& s) {
  return json{{"id", s.id},
              {"server", s.info.server},
              {"node_id", s.info.node_id},
              {"browse_path", s.info.browse_path},
              {"data_type", std::string{hist::to_string(s.info.data_type)}},
              {"unit", s.info.unit}};
}

}  // namespace sf::app::history_cli
