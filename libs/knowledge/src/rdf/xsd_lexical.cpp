#include "xsd_lexical.hpp"

#include <array>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <string>

namespace sf::knowledge::xsd {
namespace {

constexpr int kMaxDigits = 18;  // every 18-digit mantissa fits an int64

bool digit(char c) {
  return c >= '0' && c <= '9';
}

// Removes trailing zero digits of the fraction: 1.50 → 1.5, 2.0 → 2.
Decimal normalise(Decimal d) {
  while (d.scale > 0 && d.mantissa % 10 == 0) {
    d.mantissa /= 10;
    --d.scale;
  }
  if (d.mantissa == 0) {
    d.scale = 0;
  }
  return d;
}

std::optional<std::int64_t> pow10(int n) {
  std::int64_t r = 1;
  for (int i = 0; i < n; ++i) {
    if (__builtin_mul_overflow(r, 10, &r)) {
      return std::nullopt;
    }
  }
  return r;
}

// Brings a and b to the same scale; nothing on overflow.
bool align(Decimal& a, Decimal& b) {
  Decimal& lo = a.scale < b.scale ? a : b;
  const Decimal& hi = a.scale < b.scale ? b : a;
  auto factor = pow10(hi.scale - lo.scale);
  if (!factor || __builtin_mul_overflow(lo.mantissa, *factor, &lo.mantissa)) {
    return false;
  }
  lo.scale = hi.scale;
  return true;
}

int fixed_digits(std::string_view s, std::size_t pos, std::size_t n, int& out) {
  if (pos + n > s.size()) {
    return -1;
  }
  out = 0;
  for (std::size_t i = pos; i < pos + n; ++i) {
    if (!digit(s[i])) {
      return -1;
    }
    out = out * 10 + (s[i] - '0');
  }
  return 0;
}

// Days since 1970-01-01 of a proleptic Gregorian date (H. Hinnant's days_from_civil).
std::int64_t days_from_civil(std::int64_t y, int m, int d) {
  y -= m <= 2 ? 1 : 0;
  const std::int64_t era = (y >= 0 ? y : y - 399) / 400;
  const std::int64_t yoe = y - era * 400;
  const std::int64_t doy = (153 * (m + (m > 2 ? -3 : 9)) + 2) / 5 + d - 1;
  const std::int64_t doe = yoe * 365 + yoe / 4 - yoe / 100 + doy;
  return era * 146097 + doe - 719468;
}

int days_in_month(std::int64_t y, int m) {
  static constexpr std::array<int, 12> kDays{31, 28, 31, 30, 31, 30, 31, 31, 30, 31, 30, 31};
  const bool leap = (y % 4 == 0 && y % 100 != 0) || y % 400 == 0;
  return m == 2 && leap ? 29 : kDays[static_cast<std::size_t>(m - 1)];
}

// "-?yyyy-mm-dd" at the start of s; returns the position after it.
std::optional<std::size_t> parse_date_part(std::string_view s, std::int64_t& days) {
  std::size_t pos = s.starts_with('-') ? 1 : 0;
  std::size_t year_end = pos;
  while (year_end < s.size() && digit(s[year_end])) {
    ++year_end;
  }
  if (year_end - pos < 4 || year_end - pos > 9) {
    return std::nullopt;
  }
  std::int64_t year = 0;
  for (std::size_t i = pos; i < year_end; ++i) {
    year = year * 10 + (s[i] - '0');
  }
  year = pos == 1 ? -year : year;
  int month = 0;
  int day = 0;
  if (year_end + 6 > s.size() || s[year_end] != '-' || fixed_digits(s, year_end + 1, 2, month) != 0 ||
      s[year_end + 3] != '-' || fixed_digits(s, year_end + 4, 2, day) != 0) {
    return std::nullopt;
  }
  if (month < 1 || month > 12 || day < 1 || day > days_in_month(year, month)) {
    return std::nullopt;
  }
  days = days_from_civil(year, month, day);
  return year_end + 6;
}

// "hh:mm:ss(.s+)?" at pos; adds it to seconds/nanos and returns the position after it.
std::optional<std::size_t> parse_time_part(std::string_view s, std::size_t pos, Instant& t) {
  int h = 0;
  int m = 0;
  int sec = 0;
  if (fixed_digits(s, pos, 2, h) != 0 || pos + 8 > s.size() || s[pos + 2] != ':' ||
      fixed_digits(s, pos + 3, 2, m) != 0 || s[pos + 5] != ':' || fixed_digits(s, pos + 6, 2, sec) != 0) {
    return std::nullopt;
  }
  pos += 8;
  std::int32_t nanos = 0;
  if (pos < s.size() && s[pos] == '.') {
    std::size_t end = pos + 1;
    std::int32_t scale = 100000000;
    while (end < s.size() && digit(s[end])) {
      nanos += (s[end] - '0') * scale;
      scale /= 10;
      ++end;
    }
    if (end == pos + 1) {
      return std::nullopt;
    }
    pos = end;
  }
  // §3.3.7: 24:00:00 is the first instant of the next day.
  const bool end_of_day = h == 24 && m == 0 && sec == 0 && nanos == 0;
  if ((h > 23 && !end_of_day) || m > 59 || sec > 59) {
    return std::nullopt;
  }
  t.seconds += static_cast<std::int64_t>(h) * 3600 + static_cast<std::int64_t>(m) * 60 + sec;
  t.nanos = nanos;
  return pos;
}

// "Z" or "(+|-)hh:mm" at pos up to the end.
bool parse_zone(std::string_view s, std::size_t pos, Instant& t) {
  if (pos == s.size()) {
    return true;
  }
  if (s.substr(pos) == "Z") {
    t.zoned = true;
    return true;
  }
  int h = 0;
  int m = 0;
  if (s.size() - pos != 6 || (s[pos] != '+' && s[pos] != '-') || fixed_digits(s, pos + 1, 2, h) != 0 ||
      s[pos + 3] != ':' || fixed_digits(s, pos + 4, 2, m) != 0 || h > 14 || m > 59) {
    return false;
  }
  const std::int64_t offset = static_cast<std::int64_t>(h) * 3600 + static_cast<std::int64_t>(m) * 60;
  t.seconds -= s[pos] == '+' ? offset : -offset;
  t.zoned = true;
  return true;
}

std::optional<Decimal> long_division(std::int64_t num, std::int64_t den) {
  const bool negative = (num < 0) != (den < 0);
  std::uint64_t n = num < 0 ? 0 - static_cast<std::uint64_t>(num) : static_cast<std::uint64_t>(num);
  const std::uint64_t d = den < 0 ? 0 - static_cast<std::uint64_t>(den) : static_cast<std::uint64_t>(den);
  std::uint64_t q = n / d;
  std::uint64_t r = n % d;
  if (q > static_cast<std::uint64_t>(std::numeric_limits<std::int64_t>::max())) {
    return std::nullopt;
  }
  Decimal out{static_cast<std::int64_t>(q), 0};
  // XPath op:numeric-divide: at least 18 fractional digits where the mantissa allows.
  while (r != 0 && out.scale < kMaxDigits && out.mantissa < std::numeric_limits<std::int64_t>::max() / 10) {
    if (r > std::numeric_limits<std::uint64_t>::max() / 10) {
      break;
    }
    r *= 10;
    out.mantissa = out.mantissa * 10 + static_cast<std::int64_t>(r / d);
    r %= d;
    ++out.scale;
  }
  if (negative) {
    out.mantissa = -out.mantissa;
  }
  return normalise(out);
}

}  // namespace

std::optional<Decimal> parse_decimal(std::string_view s, bool allow_fraction) {
  std::size_t pos = 0;
  bool negative = false;
  if (!s.empty() && (s[0] == '+' || s[0] == '-')) {
    negative = s[0] == '-';
    pos = 1;
  }
  Decimal d;
  int digits = 0;
  bool any = false;
  bool point = false;
  for (; pos < s.size(); ++pos) {
    const char c = s[pos];
    if (c == '.' && allow_fraction && !point) {
      point = true;
      continue;
    }
    if (!digit(c)) {
      return std::nullopt;
    }
    any = true;
    if (d.mantissa == 0 && c == '0' && !point) {
      continue;  // leading zeros
    }
    if (++digits > kMaxDigits) {
      return std::nullopt;
    }
    d.mantissa = d.mantissa * 10 + (c - '0');
    d.scale += point ? 1 : 0;
  }
  if (!any) {
    return std::nullopt;
  }
  if (negative) {
    d.mantissa = -d.mantissa;
  }
  return normalise(d);
}

std::optional<double> parse_floating(std::string_view s, bool single_precision) {
  if (s == "INF" || s == "+INF") {
    return std::numeric_limits<double>::infinity();
  }
  if (s == "-INF") {
    return -std::numeric_limits<double>::infinity();
  }
  if (s == "NaN") {
    return std::numeric_limits<double>::quiet_NaN();
  }
  // Check the XSD lexical form; std::from_chars accepts a little more (e.g. "inf").
  std::size_t pos = (!s.empty() && (s[0] == '+' || s[0] == '-')) ? 1 : 0;
  const std::string_view body = s.substr(pos);
  std::size_t mantissa_digits = 0;
  std::size_t i = 0;
  for (bool point = false; i < body.size() && (digit(body[i]) || (body[i] == '.' && !point)); ++i) {
    point = point || body[i] == '.';
    mantissa_digits += digit(body[i]) ? 1U : 0U;
  }
  if (mantissa_digits == 0) {
    return std::nullopt;
  }
  if (i < body.size()) {
    if (body[i] != 'e' && body[i] != 'E') {
      return std::nullopt;
    }
    std::size_t j = i + 1 < body.size() && (body[i + 1] == '+' || body[i + 1] == '-') ? i + 2 : i + 1;
    if (j >= body.size()) {
      return std::nullopt;
    }
    for (; j < body.size(); ++j) {
      if (!digit(body[j])) {
        return std::nullopt;
      }
    }
  }
  std::string text{s[0] == '+' ? s.substr(1) : s};
  if (single_precision) {
    float f = 0;
    auto [p, ec] = std::from_chars(text.data(), text.data() + text.size(), f);
    if (ec == std::errc::result_out_of_range) {
      return std::strtod(text.c_str(), nullptr) < 0 ? -std::numeric_limits<double>::infinity()
                                                    : std::numeric_limits<double>::infinity();
    }
    return ec == std::errc{} ? std::optional<double>(static_cast<double>(f)) : std::nullopt;
  }
  return std::strtod(text.c_str(), nullptr);  // overflow → ±HUGE_VAL (= ±INF), as Java parses
}

std::optional<Instant> parse_date_time(std::string_view s, bool date_only) {
  std::int64_t days = 0;
  auto pos = parse_date_part(s, days);
  if (!pos) {
    return std::nullopt;
  }
  Instant t;
  t.seconds = days * 86400;
  if (!date_only) {
    if (*pos >= s.size() || s[*pos] != 'T') {
      return std::nullopt;
    }
    pos = parse_time_part(s, *pos + 1, t);
    if (!pos) {
      return std::nullopt;
    }
  }
  if (!parse_zone(s, *pos, t)) {
    return std::nullopt;
  }
  return t;
}

int compare_decimals(const Decimal& a, const Decimal& b) {
  Decimal x = a;
  Decimal y = b;
  if (!align(x, y)) {
    const long double p = static_cast<long double>(a.mantissa) / std::pow(10.0L, a.scale);
    const long double q = static_cast<long double>(b.mantissa) / std::pow(10.0L, b.scale);
    return p < q ? -1 : (p > q ? 1 : 0);
  }
  return x.mantissa < y.mantissa ? -1 : (x.mantissa > y.mantissa ? 1 : 0);
}

std::optional<std::int64_t> integer_arithmetic(ArithmeticOp op, std::int64_t a, std::int64_t b) {
  std::int64_t r = 0;
  switch (op) {
    case ArithmeticOp::sum:
      return __builtin_add_overflow(a, b, &r) ? std::nullopt : std::optional(r);
    case ArithmeticOp::difference:
      return __builtin_sub_overflow(a, b, &r) ? std::nullopt : std::optional(r);
    case ArithmeticOp::product:
      return __builtin_mul_overflow(a, b, &r) ? std::nullopt : std::optional(r);
    case ArithmeticOp::quotient:
      if (b == 0 || (a == std::numeric_limits<std::int64_t>::min() && b == -1)) {
        return std::nullopt;
      }
      return a / b;  // Java long division truncates toward zero, as C++ does
  }
  return std::nullopt;
}

std::optional<Decimal> decimal_arithmetic(ArithmeticOp op, const Decimal& a, const Decimal& b) {
  Decimal x = a;
  Decimal y = b;
  Decimal r;
  switch (op) {
    case ArithmeticOp::sum:
    case ArithmeticOp::difference:
      if (!align(x, y)) {
        return std::nullopt;
      }
      r.scale = x.scale;
      if (op == ArithmeticOp::sum ? __builtin_add_overflow(x.mantissa, y.mantissa, &r.mantissa)
                                  : __builtin_sub_overflow(x.mantissa, y.mantissa, &r.mantissa)) {
        return std::nullopt;
      }
      return normalise(r);
    case ArithmeticOp::product:
      if (__builtin_mul_overflow(a.mantissa, b.mantissa, &r.mantissa)) {
        return std::nullopt;
      }
      r.scale = a.scale + b.scale;
      return normalise(r);
    case ArithmeticOp::quotient:
      if (b.mantissa == 0 || !align(x, y)) {
        return std::nullopt;
      }
      return long_division(x.mantissa, y.mantissa);
  }
  return std::nullopt;
}

}  // namespace sf::knowledge::xsd

namespace sf::knowledge {

std::string java_double_string(double d) {
  if (std::isnan(d)) {
    return "NaN";
  }
  if (std::isinf(d)) {
    return d < 0 ? "-Infinity" : "Infinity";
  }
  if (d == 0) {
    return std::signbit(d) ? "-0.0" : "0.0";
  }
  // Shortest round-trip digits, then Java's layout (Double.toString): plain notation for
  // 10^-3 <= |d| < 10^7, otherwise d.dddE±n, always with a fraction digit.
  std::array<char, 64> buf{};
  auto [end, ec] =
      std::to_chars(buf.data(), buf.data() + buf.size(), std::abs(d), std::chars_format::scientific);
  const std::string_view sci(buf.data(), static_cast<std::size_t>(end - buf.data()));
  const std::size_t e = sci.find('e');
  std::string digits;
  for (char c : sci.substr(0, e)) {
    if (c != '.') {
      digits.push_back(c);
    }
  }
  int exponent = 0;
  std::from_chars(sci.data() + e + (sci[e + 1] == '+' ? 2 : 1), sci.data() + sci.size(), exponent);
  std::string out = d < 0 ? "-" : "";
  if (exponent >= -3 && exponent < 7) {
    if (exponent < 0) {
      out += "0." + std::string(static_cast<std::size_t>(-exponent - 1), '0') + digits;
    } else {
      const auto int_len = static_cast<std::size_t>(exponent) + 1;
      digits.resize(std::max(digits.size(), int_len), '0');
      const std::string frac = digits.substr(int_len);
      out += digits.substr(0, int_len) + "." + (frac.empty() ? "0" : frac);
    }
    return out;
  }
  out += digits.substr(0, 1) + "." + (digits.size() > 1 ? digits.substr(1) : "0");
  return out + "E" + std::to_string(exponent);
}

std::string decimal_string(const Decimal& d) {
  const std::uint64_t magnitude =
      d.mantissa < 0 ? 0 - static_cast<std::uint64_t>(d.mantissa) : static_cast<std::uint64_t>(d.mantissa);
  std::string digits = std::to_string(magnitude);
  if (d.scale <= 0) {
    return (d.mantissa < 0 ? "-" : "") + digits + ".0";
  }
  const auto scale = static_cast<std::size_t>(d.scale);
  if (digits.size() <= scale) {
    digits.insert(0, scale - digits.size() + 1, '0');
  }
  digits.insert(digits.size() - scale, ".");
  return (d.mantissa < 0 ? "-" : "") + digits;
}

}  // namespace sf::knowledge
