// Historian values and times as the REST API writes them (libs/dashboard/openapi.yaml).
#pragma once

#include <string>
#include <string_view>

#include <nlohmann/json.hpp>

#include "sf/core/result.hpp"
#include "sf/historian/types.hpp"

namespace sf::dashboard {

// null for an empty value, numbers, booleans and texts as JSON has them, bytes as hex text.
nlohmann::json value_json(const historian::Value& value);
// "2026-11-27T10:00:00.000Z" (milliseconds: what browsers' Date parses).
std::string time_text(historian::Timestamp t);
// A time parameter: ISO 8601 (historian::parse_time, also "now" and "-10m") or Unix milliseconds.
Result<historian::Timestamp> parse_time_param(std::string_view text, historian::Timestamp now);

}  // namespace sf::dashboard
