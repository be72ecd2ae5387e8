// What the `history` subcommands share: the --db option, opening the store,
// the time "now" (through the Clock seam), errors and JSON of values.
#pragma once

#include <memory>
#include <string>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "commands.hpp"
#include "sf/core/result.hpp"
#include "sf/historian/store.hpp"

namespace sf::app::history_cli {

inline constexpr const char* kTimeHelp =
    "ISO 8601 (UTC unless an offset is given), or relative to now like -10m, now";

// --db URL (required; SF_HISTORY_DB in the environment also works).
void add_db_option(CLI::App& cmd, std::string& db);
Result<std::unique_ptr<historian::Store>> open_db(const std::string& url);
historian::Timestamp now();
// Prints the error on stderr and gives the exit code (bad input: usage).
int fail(const Error& e);
std::string status_text(historian::StatusCode s);
nlohmann::json value_json(const historian::Value& v);
nlohmann::json series_json(const historian::Series& s);

// `history events` and `history write` (history_write.cpp).
void register_events(CLI::App& history, CommandResult& result);
void register_write(CLI::App& history, CommandResult& result);

}  // namespace sf::app::history_cli
