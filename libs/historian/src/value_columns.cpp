#include "value_columns.hpp"

#include <bit>
#include <limits>

#include <fmt/format.h>

namespace sf::historian::detail {

ValueColumns to_columns(const Value& v) {
  ValueColumns c;
  c.vtype = static_cast<int>(type_of(v));
  switch (type_of(v)) {
    case DataType::empty:
      break;
    case DataType::boolean:
      c.v_int = std::get<bool>(v) ? 1 : 0;
      break;
    case DataType::int64:
      c.v_int = std::get<std::int64_t>(v);
      break;
    case DataType::uint64:
      c.v_int = std::bit_cast<std::int64_t>(std::get<std::uint64_t>(v));
      break;
    case DataType::float64:
      c.v_real = std::get<double>(v);
      break;
    case DataType::string:
      c.v_text = std::get<std::string>(v);
      break;
    case DataType::bytes:
      c.v_blob = std::get<Bytes>(v);
      break;
  }
  return c;
}

Result<Value> from_columns(ValueColumns c) {
  const auto missing = [&](std::string_view column) {
    return make_error(Errc::malformed, fmt::format("stored value of type {} has no {}",
                                                   to_string(static_cast<DataType>(c.vtype)), column));
  };
  switch (static_cast<DataType>(c.vtype)) {
    case DataType::empty:
      return Value{};
    case DataType::boolean:
      return c.v_int ? Result<Value>{Value{*c.v_int != 0}} : missing("v_int");
    case DataType::int64:
      return c.v_int ? Result<Value>{Value{*c.v_int}} : missing("v_int");
    case DataType::uint64:
      return c.v_int ? Result<Value>{Value{std::bit_cast<std::uint64_t>(*c.v_int)}} : missing("v_int");
    case DataType::float64:
      return Value{c.v_real.value_or(std::numeric_limits<double>::quiet_NaN())};
    case DataType::string:
      return c.v_text ? Result<Value>{Value{std::move(*c.v_text)}} : missing("v_text");
    case DataType::bytes:
      // An empty BLOB may come back as NULL.
      return Value{c.v_blob ? std::move(*c.v_blob) : Bytes{}};
  }
  return make_error(Errc::malformed, fmt::format("unknown stored value type {}", c.vtype));
}

std::string numeric_sql(std::string_view real, std::string_view v_real) {
  // uint64 is stored bit-cast: negative v_int means 2^63 or more.
  return fmt::format(
      "CASE vtype WHEN 1 THEN CAST(v_int AS {0}) WHEN 2 THEN CAST(v_int AS {0}) "
      "WHEN 3 THEN (CASE WHEN v_int < 0 THEN CAST(v_int AS {0}) + 18446744073709551616.0 "
      "ELSE CAST(v_int AS {0}) END) WHEN 4 THEN {1} END",
      real, v_real);
}

}  // namespace sf::historian::detail
