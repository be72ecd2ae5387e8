#include "sf/historian/types.hpp"

#include <array>
#include <cmath>

#include <fmt/format.h>
#include <fmt/ranges.h>

namespace sf::historian {

namespace {

constexpr std::array<std::string_view, 7> kTypeNames = {"empty",   "boolean", "int64", "uint64",
                                                        "float64", "string",  "bytes"};

// FNV-1a, 64 bit (Fowler/Noll/Vo): simple, stable across platforms and
// releases, well spread for short text keys.
constexpr std::uint64_t kFnvOffset = 0xcbf29ce484222325ULL;
constexpr std::uint64_t kFnvPrime = 0x100000001b3ULL;

std::uint64_t fnv1a(std::uint64_t h, std::string_view text) {
  for (const char c : text) {
    h ^= static_cast<std::uint8_t>(c);
    h *= kFnvPrime;
  }
  return h;
}

}  // namespace

DataType type_of(const Value& v) {
  return static_cast<DataType>(v.index());
}

std::string_view to_string(DataType t) {
  const auto i = static_cast<std::size_t>(t);
  return i < kTypeNames.size() ? kTypeNames[i] : std::string_view{"unknown"};
}

std::optional<DataType> data_type_from_string(std::string_view name) {
  for (std::size_t i = 0; i < kTypeNames.size(); ++i) {
    if (kTypeNames[i] == name) {
      return static_cast<DataType>(i);
    }
  }
  return std::nullopt;
}

std::optional<double> numeric(const Value& v) {
  switch (type_of(v)) {
    case DataType::boolean:
      return std::get<bool>(v) ? 1.0 : 0.0;
    case DataType::int64:
      return static_cast<double>(std::get<std::int64_t>(v));
    case DataType::uint64:
      return static_cast<double>(std::get<std::uint64_t>(v));
    case DataType::float64:
      return std::get<double>(v);
    default:
      return std::nullopt;
  }
}

std::string format_value(const Value& v) {
  switch (type_of(v)) {
    case DataType::empty:
      return "(empty)";
    case DataType::boolean:
      return std::get<bool>(v) ? "true" : "false";
    case DataType::int64:
      return fmt::format("{}", std::get<std::int64_t>(v));
    case DataType::uint64:
      return fmt::format("{}", std::get<std::uint64_t>(v));
    case DataType::float64:
      return fmt::format("{}", std::get<double>(v));
    case DataType::string:
      return fmt::format("\"{}\"", std::get<std::string>(v));
    case DataType::bytes:
      return fmt::format("0x{:02x}", fmt::join(std::get<Bytes>(v), ""));
  }
  return {};
}

SeriesId series_id(std::string_view server, std::string_view node_id) {
  // The separator byte keeps ("ab", "c") and ("a", "bc") apart.
  std::uint64_t h = fnv1a(kFnvOffset, server);
  h = fnv1a(h, std::string_view{"\0", 1});
  h = fnv1a(h, node_id);
  const auto id = static_cast<SeriesId>(h & 0x7fff'ffff'ffff'ffffULL);
  return id == 0 ? 1 : id;
}

}  // namespace sf::historian
