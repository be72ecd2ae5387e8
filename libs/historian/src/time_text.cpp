#include "sf/historian/time_text.hpp"

#include <array>
#include <charconv>
#include <cstdlib>
#include <limits>

#include <fmt/format.h>

namespace sf::historian {

namespace {

using std::chrono::days;
using std::chrono::hours;
using std::chrono::minutes;
using std::chrono::seconds;

struct Unit {
  std::string_view name;
  std::int64_t micros;
};

// Longest names first so "ms" is not read as "m" followed by "s".
constexpr std::array<Unit, 7> kUnits{{{"us", 1},
                                      {"ms", 1'000},
                                      {"s", 1'000'000},
                                      {"m", 60'000'000},
                                      {"h", 3'600'000'000},
                                      {"d", 86'400'000'000},
                                      {"w", 604'800'000'000}}};

Error bad_time(std::string_view text, std::string_view why) {
  return make_error(
      Errc::invalid_argument,
      fmt::format("bad time '{}': {} (ISO 8601 like 2026-11-21T10:15:30Z, or now, -10m)", text, why));
}

// Reads exactly `n` digits.
bool digits(std::string_view& s, std::size_t n, int& out) {
  if (s.size() < n) {
    return false;
  }
  const auto [p, ec] = std::from_chars(s.data(), s.data() + n, out);
  if (ec != std::errc{} || p != s.data() + n) {
    return false;
  }
  s.remove_prefix(n);
  return true;
}

bool eat(std::string_view& s, char c) {
  if (!s.empty() && s.front() == c) {
    s.remove_prefix(1);
    return true;
  }
  return false;
}

// ".ffffff" (up to 6 digits are kept, more are accepted and dropped).
bool fraction(std::string_view& s, Micros& out) {
  std::int64_t us = 0;
  std::int64_t scale = 100'000;
  std::size_t n = 0;
  while (n < s.size() && s[n] >= '0' && s[n] <= '9') {
    us += (s[n] - '0') * scale;
    scale /= 10;
    ++n;
  }
  s.remove_prefix(n);
  out = Micros{us};
  return n > 0;
}

// "Z", "+01:00", "-0530", "+01" or nothing (UTC).
bool zone(std::string_view& s, minutes& offset) {
  offset = minutes{0};
  if (s.empty() || eat(s, 'Z') || eat(s, 'z')) {
    return true;
  }
  const bool negative = s.front() == '-';
  if (!eat(s, '+') && !eat(s, '-')) {
    return false;
  }
  int h = 0;
  int m = 0;
  if (!digits(s, 2, h)) {
    return false;
  }
  if (!s.empty()) {
    eat(s, ':');
    if (!digits(s, 2, m)) {
      return false;
    }
  }
  offset = hours{h} + minutes{m};
  if (negative) {
    offset = -offset;
  }
  return h <= 23 && m <= 59;
}

Result<Timestamp> parse_iso(std::string_view text) {
  std::string_view s = text;
  int y = 0;
  int mo = 0;
  int d = 0;
  if (!digits(s, 4, y) || !eat(s, '-') || !digits(s, 2, mo) || !eat(s, '-') || !digits(s, 2, d)) {
    return bad_time(text, "expected YYYY-MM-DD");
  }
  const std::chrono::year_month_day date{std::chrono::year{y}, std::chrono::month{static_cast<unsigned>(mo)},
                                         std::chrono::day{static_cast<unsigned>(d)}};
  if (!date.ok()) {
    return bad_time(text, "no such date");
  }
  Micros time_of_day{0};
  if (eat(s, 'T') || eat(s, 't') || eat(s, ' ')) {
    int h = 0;
    int mi = 0;
    int se = 0;
    Micros frac{0};
    if (!digits(s, 2, h) || !eat(s, ':') || !digits(s, 2, mi)) {
      return bad_time(text, "expected hh:mm after the date");
    }
    if (eat(s, ':') && !digits(s, 2, se)) {
      return bad_time(text, "expected seconds after hh:mm:");
    }
    if ((eat(s, '.') || eat(s, ',')) && !fraction(s, frac)) {
      return bad_time(text, "expected digits after the decimal point");
    }
    if (h > 23 || mi > 59 || se > 60) {
      return bad_time(text, "time of day out of range");
    }
    time_of_day = hours{h} + minutes{mi} + seconds{se} + frac;
  }
  minutes offset{0};
  if (!zone(s, offset) || !s.empty()) {
    return bad_time(text, "expected Z or an offset like +01:00 at the end");
  }
  return Timestamp{std::chrono::sys_days{date}} + time_of_day - offset;
}

}  // namespace

Result<Micros> parse_duration(std::string_view text) {
  std::string_view s = text;
  if (s.empty()) {
    return make_error(Errc::invalid_argument, "empty duration (e.g. 500ms, 1s, 10m, 7d)");
  }
  Micros total{0};
  while (!s.empty()) {
    std::int64_t n = 0;
    const auto [p, ec] = std::from_chars(s.data(), s.data() + s.size(), n);
    if (ec != std::errc{} || n < 0) {
      return make_error(Errc::invalid_argument,
                        fmt::format("bad duration '{}': expected a number (e.g. 500ms, 1s, 10m, 7d)", text));
    }
    s.remove_prefix(static_cast<std::size_t>(p - s.data()));
    const Unit* unit = nullptr;
    for (const auto& u : kUnits) {
      if (s.starts_with(u.name) && (unit == nullptr || u.name.size() > unit->name.size())) {
        unit = &u;
      }
    }
    if (unit == nullptr) {
      return make_error(
          Errc::invalid_argument,
          fmt::format("bad duration '{}': unit missing or unknown (us, ms, s, m, h, d, w)", text));
    }
    s.remove_prefix(unit->name.size());
    if (n > (std::numeric_limits<std::int64_t>::max() - total.count()) / unit->micros) {
      return make_error(Errc::invalid_argument, fmt::format("bad duration '{}': too long", text));
    }
    total += Micros{n * unit->micros};
  }
  return total;
}

Result<Timestamp> parse_time(std::string_view text, Timestamp now) {
  std::string_view s = text;
  if (s.starts_with("now")) {
    s.remove_prefix(3);
    if (s.empty()) {
      return now;
    }
  }
  if (s.starts_with('-') || s.starts_with('+')) {
    auto d = parse_duration(s.substr(1));
    if (!d) {
      return bad_time(text, d.error().message);
    }
    return s.front() == '-' ? now - *d : now + *d;
  }
  return parse_iso(text);
}

std::string format_time(Timestamp t) {
  const auto day = std::chrono::floor<days>(t);
  const std::chrono::year_month_day date{day};
  const std::chrono::hh_mm_ss tod{t - day};
  std::string out = fmt::format("{:04}-{:02}-{:02}T{:02}:{:02}:{:02}", static_cast<int>(date.year()),
                                static_cast<unsigned>(date.month()), static_cast<unsigned>(date.day()),
                                tod.hours().count(), tod.minutes().count(), tod.seconds().count());
  if (const auto us = tod.subseconds().count(); us != 0) {
    out += fmt::format(".{:06}", us);
  }
  return out + "Z";
}

}  // namespace sf::historian
