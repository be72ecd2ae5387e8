// How a typed Value is laid out in the samples table of both back ends: a
// type tag and one of four nullable columns. bool/int64/uint64 share v_int
// (uint64 bit-cast, so 2^63..2^64-1 read back exactly), float64 is v_real,
// string v_text, bytes v_blob.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

#include "sf/core/result.hpp"
#include "sf/historian/types.hpp"

namespace sf::historian::detail {

struct ValueColumns {
  int vtype = 0;
  std::optional<std::int64_t> v_int{};
  std::optional<double> v_real{};
  std::optional<std::string> v_text{};
  std::optional<Bytes> v_blob{};
};

ValueColumns to_columns(const Value& v);
// Fails (Errc::malformed) when the tag is unknown or its column is missing.
// A float64 whose v_real is NULL is NaN: SQLite stores NaN as NULL.
Result<Value> from_columns(ValueColumns columns);

// SQL for the value as a double, for min/max/avg; NULL for non-numeric types.
// `real` is the back end's double type for casts ("REAL", "float8"), `v_real`
// the expression for a float64 (PostgreSQL maps NaN to NULL there, as SQLite
// stores it, so both back ends leave NaN out of aggregates).
std::string numeric_sql(std::string_view real, std::string_view v_real);

}  // namespace sf::historian::detail
