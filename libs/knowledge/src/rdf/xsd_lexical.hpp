// XSD lexical spaces and exact decimal arithmetic behind literal.cpp (XML Schema 1.1 Part 2).
#pragma once

#include <cstdint>
#include <optional>
#include <string_view>

#include "sf/knowledge/literal.hpp"

namespace sf::knowledge::xsd {

// §3.3.3.1 decimal "(+|-)?([0-9]+(\.[0-9]*)?|\.[0-9]+)"; with allow_fraction false the integer
// form "(+|-)?[0-9]+" (§3.4.13). Nothing when malformed or beyond 18 significant digits.
std::optional<Decimal> parse_decimal(std::string_view text, bool allow_fraction);
// §3.3.5.1 double / §3.3.4.1 float, including INF, -INF and NaN; floats are rounded to single
// precision and returned widened.
std::optional<double> parse_floating(std::string_view text, bool single_precision);

struct Instant {
  std::int64_t seconds = 0;
  std::int32_t nanos = 0;
  bool zoned = false;
};
// §3.3.7.1 dateTime "-?yyyy-mm-ddThh:mm:ss(.s+)?(Z|(+|-)hh:mm)?", or with date_only §3.3.9.1
// "-?yyyy-mm-dd(zone)?"; zoned values are normalised to UTC.
std::optional<Instant> parse_date_time(std::string_view text, bool date_only);

int compare_decimals(const Decimal& a, const Decimal& b);
std::optional<std::int64_t> integer_arithmetic(ArithmeticOp op, std::int64_t a, std::int64_t b);
std::optional<Decimal> decimal_arithmetic(ArithmeticOp op, const Decimal& a, const Decimal& b);

}  // namespace sf::knowledge::xsd
