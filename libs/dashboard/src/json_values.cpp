#include "json_values.hpp"

#include <charconv>
#include <cmath>

#include <fmt/chrono.h>
#include <fmt/format.h>

#include "sf/historian/time_text.hpp"

namespace sf::dashboard {

nlohmann::json value_json(const historian::Value& value) {
  return std::visit(
      [](const auto& v) -> nlohmann::json {
        using T = std::decay_t<decltype(v)>;
        if constexpr (std::is_same_v<T, std::monostate>) {
          return nullptr;
        } else if constexpr (std::is_same_v<T, double>) {
          return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr);  // JSON has no NaN
        } else if constexpr (std::is_same_v<T, Bytes>) {
          std::string hex;
          for (auto b : v) {
            hex += fmt::format("{:02x}", b);
          }
          return hex;
        } else {
          return v;
        }
      },
      value);
}

std::string time_text(historian::Timestamp t) {
  const auto ms = std::chrono::floor<std::chrono::milliseconds>(t);
  return fmt::format("{:%Y-%m-%dT%H:%M:%S}.{:03d}Z", std::chrono::floor<std::chrono::seconds>(ms),
                     (ms.time_since_epoch() % std::chrono::seconds(1)).count() +
                         ((ms.time_since_epoch().count() % 1000) < 0 ? 1000 : 0));
}

Result<historian::Timestamp> parse_time_param(std::string_view text, historian::Timestamp now) {
  std::int64_t ms = 0;
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), ms);
  if (error == std::errc{} && end == text.data() + text.size() && !text.empty()) {
    if (ms < 0 || ms > 253'402'300'799'000) {  // before 1970 or after 9999: not a time we keep
      return make_error(Errc::invalid_argument, fmt::format("time {} ms is out of range", ms));
    }
    return historian::Timestamp{std::chrono::milliseconds{ms}};
  }
  return historian::parse_time(text, now);
}

}  // namespace sf::dashboard
