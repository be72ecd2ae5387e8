// Lexical-to-value mapping of the XSD datatypes the reasoner interprets (XML Schema 1.1 Part 2
// §3.3.3 decimal, §3.3.4 float, §3.3.5 double, §3.3.2 boolean, §3.3.7 dateTime, §3.3.9 date,
// §3.4 the integer types) and Jena-compatible value equality and order.
#include "sf/knowledge/literal.hpp"

#include <array>
#include <bit>
#include <charconv>
#include <cmath>
#include <functional>
#include <limits>

#include "sf/knowledge/vocab.hpp"
#include "xsd_lexical.hpp"

namespace sf::knowledge {
namespace {

// XSD whitespace facet "collapse" as far as single-token values go: strip surrounding blanks.
std::string_view collapse(std::string_view s) {
  const auto blank = [](char c) { return c == ' ' || c == '\t' || c == '\n' || c == '\r'; };
  while (!s.empty() && blank(s.front())) {
    s.remove_prefix(1);
  }
  while (!s.empty() && blank(s.back())) {
    s.remove_suffix(1);
  }
  return s;
}

struct IntegerRange {
  std::string_view local;
  std::int64_t min;
  std::int64_t max;
};

constexpr std::int64_t kMin64 = std::numeric_limits<std::int64_t>::min();
constexpr std::int64_t kMax64 = std::numeric_limits<std::int64_t>::max();

// XSD Part 2 §3.4.13–§3.4.25: the built-in types derived from xsd:integer and their bounds
// (unbounded ones are limited to 64 bits here).
constexpr std::array<IntegerRange, 13> kIntegerTypes{{
    {"integer", kMin64, kMax64},
    {"nonPositiveInteger", kMin64, 0},
    {"negativeInteger", kMin64, -1},
    {"long", kMin64, kMax64},
    {"int", -2147483648LL, 2147483647LL},
    {"short", -32768, 32767},
    {"byte", -128, 127},
    {"nonNegativeInteger", 0, kMax64},
    {"unsignedLong", 0, kMax64},
    {"unsignedInt", 0, 4294967295LL},
    {"unsignedShort", 0, 65535},
    {"unsignedByte", 0, 255},
    {"positiveInteger", 1, kMax64},
}};

const IntegerRange* integer_type(std::string_view local) {
  for (const auto& t : kIntegerTypes) {
    if (t.local == local) {
      return &t;
    }
  }
  return nullptr;
}

LiteralValue parse_typed(std::string_view lexical, std::string_view datatype) {
  LiteralValue v;
  v.lexical = lexical;
  v.datatype = datatype;
  if (datatype.substr(0, vocab::kXsd.size()) != vocab::kXsd) {
    return v;
  }
  const std::string_view local = datatype.substr(vocab::kXsd.size());
  const std::string_view text = collapse(lexical);
  if (local == "decimal") {
    if (auto d = xsd::parse_decimal(text, true)) {
      v.cls = ValueClass::decimal;
      v.decimal = *d;
    }
  } else if (const IntegerRange* range = integer_type(local)) {
    auto d = xsd::parse_decimal(text, false);
    if (d && d->mantissa >= range->min && d->mantissa <= range->max) {
      v.cls = ValueClass::decimal;
      v.decimal = *d;
    }
  } else if (local == "double" || local == "float") {
    if (auto n = xsd::parse_floating(text, local == "float")) {
      v.cls = local == "float" ? ValueClass::float_ : ValueClass::double_;
      v.number = *n;
    }
  } else if (local == "boolean") {
    if (text == "true" || text == "1" || text == "false" || text == "0") {
      v.cls = ValueClass::boolean;
      v.boolean = text == "true" || text == "1";
    }
  } else if (local == "dateTime" || local == "date") {
    if (auto t = xsd::parse_date_time(text, local == "date")) {
      v.cls = ValueClass::date_time;
      v.seconds = t->seconds;
      v.nanos = t->nanos;
      v.zoned = t->zoned;
    }
  }
  return v;
}

char lower(char c) {
  return (c >= 'A' && c <= 'Z') ? static_cast<char>(c - 'A' + 'a') : c;
}

bool equal_ignore_case(std::string_view a, std::string_view b) {
  if (a.size() != b.size()) {
    return false;
  }
  for (std::size_t i = 0; i < a.size(); ++i) {
    if (lower(a[i]) != lower(b[i])) {
      return false;
    }
  }
  return true;
}

std::size_t mix(std::size_t h, std::size_t v) {
  return h ^ (v + 0x9e3779b97f4a7c15ULL + (h << 6) + (h >> 2));
}

// Java's Double.equals: all NaNs are one value, 0.0 and -0.0 are two.
std::uint64_t double_key(double d) {
  return std::isnan(d) ? 0x7ff8000000000000ULL : std::bit_cast<std::uint64_t>(d);
}

int three_way(double a, double b) {
  // Java: (d1 < d2) ? -1 : ((d1 == d2) ? 0 : +1), so NaN sorts after everything.
  if (a < b) {
    return -1;
  }
  return a == b ? 0 : 1;
}

}  // namespace

double Decimal::to_double() const {
  return static_cast<double>(mantissa) / std::pow(10.0, static_cast<double>(scale));
}

LiteralValue parse_literal(std::string_view lexical, std::string_view datatype, std::string_view lang) {
  if (!lang.empty()) {
    LiteralValue v;
    v.cls = ValueClass::lang_string;
    v.lexical = lexical;
    v.lang = lang;
    return v;
  }
  if (datatype.empty() || datatype == vocab::kXsdString) {
    LiteralValue v;
    v.cls = ValueClass::string;
    v.lexical = lexical;
    return v;
  }
  return parse_typed(lexical, datatype);
}

bool same_value(const LiteralValue& a, const LiteralValue& b) {
  if (a.cls != b.cls) {
    return false;
  }
  switch (a.cls) {
    case ValueClass::other:
      return a.lexical == b.lexical && a.datatype == b.datatype;
    case ValueClass::string:
      return a.lexical == b.lexical;
    case ValueClass::lang_string:
      return a.lexical == b.lexical && equal_ignore_case(a.lang, b.lang);
    case ValueClass::decimal:
      return a.decimal.mantissa == b.decimal.mantissa && a.decimal.scale == b.decimal.scale;
    case ValueClass::float_:
    case ValueClass::double_:
      return double_key(a.number) == double_key(b.number);
    case ValueClass::boolean:
      return a.boolean == b.boolean;
    case ValueClass::date_time:
      return a.seconds == b.seconds && a.nanos == b.nanos && a.zoned == b.zoned;
  }
  return false;
}

std::size_t value_hash(const LiteralValue& v) {
  std::size_t h = static_cast<std::size_t>(v.cls) * 0x100000001b3ULL;
  switch (v.cls) {
    case ValueClass::other:
      return mix(mix(h, std::hash<std::string_view>{}(v.lexical)), std::hash<std::string_view>{}(v.datatype));
    case ValueClass::string:
      return mix(h, std::hash<std::string_view>{}(v.lexical));
    case ValueClass::lang_string:
      for (char c : v.lang) {
        h = mix(h, static_cast<unsigned char>(lower(c)));
      }
      return mix(h, std::hash<std::string_view>{}(v.lexical));
    case ValueClass::decimal:
      return mix(mix(h, static_cast<std::size_t>(v.decimal.mantissa)),
                 static_cast<std::size_t>(v.decimal.scale));
    case ValueClass::float_:
    case ValueClass::double_:
      return mix(h, double_key(v.number));
    case ValueClass::boolean:
      return mix(h, v.boolean ? 1 : 0);
    case ValueClass::date_time:
      return mix(mix(mix(h, static_cast<std::size_t>(v.seconds)), static_cast<std::size_t>(v.nanos)),
                 v.zoned);
  }
  return h;
}

std::optional<int> compare_values(const LiteralValue& a, const LiteralValue& b) {
  if (a.numeric() && b.numeric()) {
    if (a.cls == ValueClass::decimal && b.cls == ValueClass::decimal) {
      return xsd::compare_decimals(a.decimal, b.decimal);
    }
    const double x = a.cls == ValueClass::decimal ? a.decimal.to_double() : a.number;
    const double y = b.cls == ValueClass::decimal ? b.decimal.to_double() : b.number;
    return three_way(x, y);
  }
  if (a.cls == ValueClass::date_time && b.cls == ValueClass::date_time) {
    if (a.zoned != b.zoned) {
      return std::nullopt;  // XSD Part 2 §D.2.2: indeterminate
    }
    if (a.seconds != b.seconds) {
      return a.seconds < b.seconds ? -1 : 1;
    }
    return a.nanos == b.nanos ? 0 : (a.nanos < b.nanos ? -1 : 1);
  }
  return std::nullopt;
}

std::optional<MadeLiteral> arithmetic(ArithmeticOp op, const LiteralValue& a, const LiteralValue& b) {
  if (!a.numeric() || !b.numeric()) {
    return std::nullopt;
  }
  if (a.cls != ValueClass::decimal || b.cls != ValueClass::decimal) {
    const double x = a.cls == ValueClass::decimal ? a.decimal.to_double() : a.number;
    const double y = b.cls == ValueClass::decimal ? b.decimal.to_double() : b.number;
    double r = 0;
    switch (op) {
      case ArithmeticOp::sum:
        r = x + y;
        break;
      case ArithmeticOp::difference:
        r = x - y;
        break;
      case ArithmeticOp::product:
        r = x * y;
        break;
      case ArithmeticOp::quotient:
        r = x / y;
        break;
    }
    return MadeLiteral{java_double_string(r), vocab::kXsdDouble};
  }
  if (a.decimal.integral() && b.decimal.integral()) {
    auto r = xsd::integer_arithmetic(op, a.decimal.mantissa, b.decimal.mantissa);
    if (!r) {
      return std::nullopt;
    }
    const bool fits_int =
        *r >= std::numeric_limits<std::int32_t>::min() && *r <= std::numeric_limits<std::int32_t>::max();
    return MadeLiteral{std::to_string(*r), fits_int ? vocab::kXsdInt : vocab::kXsdLong};
  }
  auto r = xsd::decimal_arithmetic(op, a.decimal, b.decimal);
  if (!r) {
    return std::nullopt;
  }
  return MadeLiteral{decimal_string(*r), vocab::kXsdDecimal};
}

}  // namespace sf::knowledge
