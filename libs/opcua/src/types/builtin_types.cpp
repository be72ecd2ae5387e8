#include "sf/opcua/builtin_types.hpp"

#include <algorithm>
#include <array>
#include <charconv>
#include <cstring>
#include <limits>
#include <optional>
#include <ostream>

#include <fmt/format.h>

#include "sf/core/text.hpp"

namespace sf::opcua {

std::string_view to_string(BuiltinType type) {
  static constexpr std::array<std::string_view, 26> kNames = {
      "Null",           "Boolean",       "SByte",         "Byte",          "Int16",           "UInt16",
      "Int32",          "UInt32",        "Int64",         "UInt64",        "Float",           "Double",
      "String",         "DateTime",      "Guid",          "ByteString",    "XmlElement",      "NodeId",
      "ExpandedNodeId", "StatusCode",    "QualifiedName", "LocalizedText", "ExtensionObject", "DataValue",
      "Variant",        "DiagnosticInfo"};
  const auto i = static_cast<std::size_t>(type);
  return i < kNames.size() ? kNames[i] : std::string_view("Unknown");
}

ByteString ByteString::from_text(std::string_view text) {
  Bytes bytes(text.size());
  if (!text.empty()) {
    std::memcpy(bytes.data(), text.data(), text.size());
  }
  return ByteString(std::move(bytes));
}

// ---- Guid -------------------------------------------------------------------------------------

namespace {

// Parses `digits` hex digits of text starting at pos into value.
bool parse_hex(std::string_view text, std::size_t pos, std::size_t digits, std::uint64_t& value) {
  value = 0;
  for (std::size_t i = 0; i < digits; ++i) {
    const int v = hex_value(text[pos + i]);
    if (v < 0) {
      return false;
    }
    value = (value << 4U) | static_cast<std::uint64_t>(v);
  }
  return true;
}

}  // namespace

Result<Guid> Guid::parse(std::string_view text) {
  if (text.size() == 38 && text.front() == '{' && text.back() == '}') {
    text = text.substr(1, 36);
  }
  const auto bad = [&] { return make_error(Errc::malformed, fmt::format("invalid Guid '{}'", text)); };
  if (text.size() != 36 || text[8] != '-' || text[13] != '-' || text[18] != '-' || text[23] != '-') {
    return bad();
  }
  Guid g;
  std::uint64_t v = 0;
  if (!parse_hex(text, 0, 8, v)) {
    return bad();
  }
  g.data1 = static_cast<std::uint32_t>(v);
  if (!parse_hex(text, 9, 4, v)) {
    return bad();
  }
  g.data2 = static_cast<std::uint16_t>(v);
  if (!parse_hex(text, 14, 4, v)) {
    return bad();
  }
  g.data3 = static_cast<std::uint16_t>(v);
  static constexpr std::array<std::size_t, 8> kData4At = {19, 21, 24, 26, 28, 30, 32, 34};
  for (std::size_t i = 0; i < 8; ++i) {
    if (!parse_hex(text, kData4At[i], 2, v)) {
      return bad();
    }
    g.data4[i] = static_cast<std::uint8_t>(v);
  }
  return g;
}

std::string to_string(const Guid& g) {
  return fmt::format("{:08X}-{:04X}-{:04X}-{:02X}{:02X}-{:02X}{:02X}{:02X}{:02X}{:02X}{:02X}", g.data1,
                     g.data2, g.data3, g.data4[0], g.data4[1], g.data4[2], g.data4[3], g.data4[4], g.data4[5],
                     g.data4[6], g.data4[7]);
}

// ---- DateTime ---------------------------------------------------------------------------------

namespace {

using Ticks = std::chrono::duration<std::int64_t, std::ratio<1, DateTime::kTicksPerSecond>>;
// 1601-01-01 is this many days before 1970-01-01.
constexpr std::int64_t kDaysFrom1601To1970 = 134'774;
constexpr std::int64_t kTicksPerDay = 86'400LL * DateTime::kTicksPerSecond;
// OPC 10000-6 §5.2.2.5: 9999-12-31 23:59:59 and later encode as the maximum.
constexpr std::int64_t kLatestTicks =
    (std::chrono::sys_days{std::chrono::year{9999} / 12 / 31}.time_since_epoch().count() +
     kDaysFrom1601To1970) *
        kTicksPerDay +
    (86'399LL * DateTime::kTicksPerSecond);

}  // namespace

DateTime DateTime::from_system_clock(std::chrono::system_clock::time_point t) {
  const auto since_unix = std::chrono::floor<Ticks>(t.time_since_epoch()).count();
  if (since_unix <= -kUnixEpochTicks) {
    return min();
  }
  if (since_unix >= kLatestTicks - kUnixEpochTicks) {
    return max();
  }
  return DateTime{since_unix + kUnixEpochTicks};
}

DateTime DateTime::from_unix_seconds(std::int64_t seconds) {
  if (seconds <= -(kUnixEpochTicks / kTicksPerSecond)) {
    return min();
  }
  if (seconds >= (kLatestTicks - kUnixEpochTicks) / kTicksPerSecond) {
    return max();
  }
  return DateTime{seconds * kTicksPerSecond + kUnixEpochTicks};
}

namespace {

// Reads exactly `digits` decimal digits at text[at...]; -1 if they are not all digits.
std::int64_t fixed_digits(std::string_view text, std::size_t at, std::size_t digits) {
  if (at + digits > text.size()) {
    return -1;
  }
  std::int64_t value = 0;
  for (std::size_t i = at; i < at + digits; ++i) {
    if (text[i] < '0' || text[i] > '9') {
      return -1;
    }
    value = value * 10 + (text[i] - '0');
  }
  return value;
}

// "+hh:mm" / "-hh:mm" / "Z" / "" at text[at...] as seconds east of UTC; nullopt if malformed.
std::optional<std::int64_t> zone_offset(std::string_view text, std::size_t at) {
  const std::string_view zone = text.substr(at);
  if (zone.empty() || zone == "Z") {
    return 0;
  }
  if (zone.size() != 6 || (zone[0] != '+' && zone[0] != '-') || zone[3] != ':') {
    return std::nullopt;
  }
  const std::int64_t hours = fixed_digits(zone, 1, 2);
  const std::int64_t minutes = fixed_digits(zone, 4, 2);
  if (hours < 0 || hours > 14 || minutes < 0 || minutes > 59) {
    return std::nullopt;
  }
  return (zone[0] == '-' ? -1 : 1) * (hours * 3600 + minutes * 60);
}

}  // namespace

Result<DateTime> DateTime::parse(std::string_view text) {
  auto malformed = [&text] {
    return make_error(Errc::malformed,
                      fmt::format("'{}' is not an xs:dateTime (YYYY-MM-DDThh:mm:ss[.f][Z|±hh:mm])", text));
  };
  // YYYY-MM-DDThh:mm:ss is 19 characters with separators at fixed places.
  if (text.size() < 19 || text[4] != '-' || text[7] != '-' || text[10] != 'T' || text[13] != ':' ||
      text[16] != ':') {
    return malformed();
  }
  const std::int64_t year = fixed_digits(text, 0, 4);
  const std::int64_t month = fixed_digits(text, 5, 2);
  const std::int64_t day = fixed_digits(text, 8, 2);
  const std::int64_t hour = fixed_digits(text, 11, 2);
  const std::int64_t minute = fixed_digits(text, 14, 2);
  const std::int64_t second = fixed_digits(text, 17, 2);
  const std::chrono::year_month_day ymd{std::chrono::year{static_cast<int>(year)},
                                        std::chrono::month{static_cast<unsigned>(month)},
                                        std::chrono::day{static_cast<unsigned>(day)}};
  if (year < 0 || !ymd.ok() || hour < 0 || hour > 23 || minute < 0 || minute > 59 || second < 0 ||
      second > 60) {
    return malformed();
  }
  std::size_t at = 19;
  std::int64_t fraction_ticks = 0;
  if (at < text.size() && text[at] == '.') {
    std::int64_t scale = kTicksPerSecond;
    for (++at; at < text.size() && text[at] >= '0' && text[at] <= '9'; ++at) {
      scale /= 10;  // digits beyond the 7th (100 ns) are dropped
      fraction_ticks += (text[at] - '0') * scale;
    }
  }
  const auto offset = zone_offset(text, at);
  if (!offset) {
    return malformed();
  }
  const std::int64_t unix_seconds = std::chrono::sys_days{ymd}.time_since_epoch().count() * 86'400LL +
                                    hour * 3600 + minute * 60 + second - *offset;
  const DateTime whole = from_unix_seconds(unix_seconds);
  if (whole.ticks() <= 0 || whole == max()) {
    return whole;
  }
  return DateTime{whole.ticks() + fraction_ticks};
}

std::chrono::system_clock::time_point DateTime::to_system_clock() const {
  using Clock = std::chrono::system_clock;
  using Rep = Clock::duration::rep;
  if (ticks_ <= 0) {
    return Clock::time_point::min();
  }
  const std::int64_t since_unix = ticks_ - kUnixEpochTicks;  // no overflow: ticks_ > 0
  const auto as_clock = std::chrono::duration_cast<Clock::duration>(Ticks{1});
  const Rep per_tick = as_clock.count() > 0 ? as_clock.count() : 1;
  if (since_unix > std::numeric_limits<Rep>::max() / per_tick) {
    return Clock::time_point::max();
  }
  if (since_unix < std::numeric_limits<Rep>::min() / per_tick) {
    return Clock::time_point::min();
  }
  return Clock::time_point{std::chrono::duration_cast<Clock::duration>(Ticks{since_unix})};
}

std::string to_string(DateTime value) {
  const std::int64_t ticks = value.ticks();
  if (ticks < 0) {
    return fmt::format("DateTime({})", ticks);
  }
  const std::int64_t days = ticks / kTicksPerDay;
  std::int64_t rest = ticks % kTicksPerDay;
  const std::chrono::year_month_day ymd{std::chrono::sys_days{std::chrono::days{days - kDaysFrom1601To1970}}};
  const std::int64_t fraction = rest % DateTime::kTicksPerSecond;
  rest /= DateTime::kTicksPerSecond;
  const auto text = fmt::format("{:04}-{:02}-{:02}T{:02}:{:02}:{:02}", static_cast<int>(ymd.year()),
                                static_cast<unsigned>(ymd.month()), static_cast<unsigned>(ymd.day()),
                                rest / 3600, (rest / 60) % 60, rest % 60);
  return fraction == 0 ? text + "Z" : fmt::format("{}.{:07}Z", text, fraction);
}

// ---- NodeId -----------------------------------------------------------------------------------

std::uint32_t NodeId::numeric() const {
  const auto* n = std::get_if<std::uint32_t>(&identifier);
  return n != nullptr ? *n : 0;
}

bool NodeId::is_null() const {
  if (namespace_index != 0) {
    return false;
  }
  switch (type()) {
    case NodeIdType::Numeric:
      return numeric() == 0;
    case NodeIdType::String:
      return std::get<String>(identifier).empty();
    case NodeIdType::Guid:
      return std::get<Guid>(identifier).is_null();
    case NodeIdType::Opaque:
      return std::get<ByteString>(identifier).empty();
  }
  return false;
}

std::size_t NodeId::hash() const {
  std::size_t h = 0;
  switch (type()) {
    case NodeIdType::Numeric:
      h = std::hash<std::uint32_t>{}(numeric());
      break;
    case NodeIdType::String:
      h = std::hash<std::string_view>{}(std::get<String>(identifier).view());
      break;
    case NodeIdType::Guid: {
      const Guid& g = std::get<Guid>(identifier);
      std::uint64_t tail = 0;
      std::memcpy(&tail, g.data4.data(), sizeof(tail));
      h = std::hash<std::uint64_t>{}(tail ^ (std::uint64_t{g.data1} << 32U) ^
                                     (std::uint64_t{g.data2} << 16U) ^ g.data3);
      break;
    }
    case NodeIdType::Opaque: {
      const Bytes& b = std::get<ByteString>(identifier).bytes();
      h = std::hash<std::string_view>{}(std::string_view(reinterpret_cast<const char*>(b.data()), b.size()));
      break;
    }
  }
  return h ^ (std::size_t{namespace_index} * 0x9E3779B97F4A7C15ULL) ^ identifier.index();
}

namespace {

template <typename T>
bool parse_unsigned(std::string_view text, T& out) {
  const char* end = text.data() + text.size();
  auto [p, ec] = std::from_chars(text.data(), end, out);
  return ec == std::errc{} && p == end && !text.empty();
}

Result<NodeId> parse_identifier(std::uint16_t ns, std::string_view text, std::string_view whole) {
  const auto bad = [&](std::string_view why) {
    return make_error(Errc::malformed, fmt::format("invalid NodeId '{}': {}", whole, why));
  };
  if (text.size() < 2 || text[1] != '=') {
    return bad("expected i=, s=, g= or b=");
  }
  const std::string_view value = text.substr(2);
  switch (text[0]) {
    case 'i': {
      std::uint32_t id = 0;
      if (!parse_unsigned(value, id)) {
        return bad("numeric identifier is not a UInt32");
      }
      return NodeId(ns, id);
    }
    case 's':
      return NodeId(ns, String(value));
    case 'g': {
      auto g = Guid::parse(value);
      if (!g) {
        return bad(g.error().message);
      }
      return NodeId(ns, *g);
    }
    case 'b': {
      auto bytes = base64_decode(value);
      if (!bytes) {
        return bad(bytes.error().message);
      }
      return NodeId(ns, ByteString(std::move(*bytes)));
    }
    default:
      return bad("unknown identifier type");
  }
}

}  // namespace

Result<NodeId> NodeId::parse(std::string_view text) {
  std::uint16_t ns = 0;
  std::string_view rest = text;
  if (rest.starts_with("ns=")) {
    const auto semi = rest.find(';');
    if (semi == std::string_view::npos || !parse_unsigned(rest.substr(3, semi - 3), ns)) {
      return make_error(Errc::malformed, fmt::format("invalid NodeId '{}': bad namespace index", text));
    }
    rest = rest.substr(semi + 1);
  }
  return parse_identifier(ns, rest, text);
}

namespace {

std::string identifier_text(const NodeId& id) {
  switch (id.type()) {
    case NodeIdType::Numeric:
      return fmt::format("i={}", id.numeric());
    case NodeIdType::String:
      return "s=" + std::get<String>(id.identifier).str();
    case NodeIdType::Guid:
      return "g=" + to_string(std::get<Guid>(id.identifier));
    case NodeIdType::Opaque:
      return "b=" + base64_encode(std::get<ByteString>(id.identifier).span());
  }
  return {};
}

// OPC 10000-6 §5.3.1.11: ';' and '%' in a namespace URI are percent-escaped.
std::string escape_uri(std::string_view uri) {
  std::string out;
  out.reserve(uri.size());
  for (char c : uri) {
    if (c == ';') {
      out += "%3B";
    } else if (c == '%') {
      out += "%25";
    } else {
      out += c;
    }
  }
  return out;
}

}  // namespace

std::string to_string(const NodeId& value) {
  if (value.namespace_index == 0) {
    return identifier_text(value);
  }
  return fmt::format("ns={};{}", value.namespace_index, identifier_text(value));
}

std::string to_string(const ExpandedNodeId& value) {
  std::string out;
  if (value.server_index != 0) {
    out += fmt::format("svr={};", value.server_index);
  }
  if (!value.namespace_uri.is_null()) {
    return out +
           fmt::format("nsu={};{}", escape_uri(value.namespace_uri.view()), identifier_text(value.node_id));
  }
  return out + to_string(value.node_id);
}

// ---- Strings and names -----------------------------------------------------------------------

std::string to_string(const String& value) {
  if (value.is_null()) {
    return "null";
  }
  std::string out = "\"";
  for (char c : value.view()) {
    const auto u = static_cast<unsigned char>(c);
    if (c == '"' || c == '\\') {
      out += '\\';
      out += c;
    } else if (u < 0x20U) {
      out += fmt::format("\\x{:02x}", u);
    } else {
      out += c;
    }
  }
  return out + "\"";
}

std::string to_string(const ByteString& value) {
  if (value.is_null()) {
    return "null";
  }
  constexpr std::size_t kShown = 32;
  std::string out = "0x";
  const Bytes& b = value.bytes();
  for (std::size_t i = 0; i < b.size() && i < kShown; ++i) {
    out += fmt::format("{:02x}", b[i]);
  }
  if (b.size() > kShown) {
    out += fmt::format("...({} bytes)", b.size());
  }
  return out;
}

std::string to_string(const XmlElement& value) {
  return to_string(value.xml);
}

std::string to_string(const QualifiedName& value) {
  if (value.namespace_index == 0) {
    return value.name.str();
  }
  return fmt::format("{}:{}", value.namespace_index, value.name.view());
}

std::string to_string(const LocalizedText& value) {
  std::string out = to_string(value.text);
  if (!value.locale.empty()) {
    out += "@" + value.locale.str();
  }
  return out;
}

std::ostream& operator<<(std::ostream& os, const String& value) {
  return os << to_string(value);
}
std::ostream& operator<<(std::ostream& os, const ByteString& value) {
  return os << to_string(value);
}
std::ostream& operator<<(std::ostream& os, const Guid& value) {
  return os << to_string(value);
}
std::ostream& operator<<(std::ostream& os, DateTime value) {
  return os << to_string(value);
}
std::ostream& operator<<(std::ostream& os, const NodeId& value) {
  return os << to_string(value);
}
std::ostream& operator<<(std::ostream& os, const ExpandedNodeId& value) {
  return os << to_string(value);
}
std::ostream& operator<<(std::ostream& os, const QualifiedName& value) {
  return os << to_string(value);
}
std::ostream& operator<<(std::ostream& os, const LocalizedText& value) {
  return os << to_string(value);
}

// ---- Base64 (RFC 4648 §4) --------------------------------------------------------------------

namespace {
constexpr std::string_view kBase64 = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";

int base64_value(char c) {
  const auto pos = kBase64.find(c);
  return pos == std::string_view::npos ? -1 : static_cast<int>(pos);
}
}  // namespace

std::string base64_encode(ByteSpan bytes) {
  std::string out;
  out.reserve((bytes.size() + 2) / 3 * 4);
  for (std::size_t i = 0; i < bytes.size(); i += 3) {
    const std::size_t n = std::min<std::size_t>(3, bytes.size() - i);
    std::uint32_t chunk = std::uint32_t{bytes[i]} << 16U;
    if (n > 1) {
      chunk |= std::uint32_t{bytes[i + 1]} << 8U;
    }
    if (n > 2) {
      chunk |= bytes[i + 2];
    }
    for (std::size_t k = 0; k < 4; ++k) {
      out += k <= n ? kBase64[(chunk >> (18U - 6U * k)) & 0x3FU] : '=';
    }
  }
  return out;
}

Result<Bytes> base64_decode(std::string_view text) {
  if (text.size() % 4 != 0) {
    return make_error(Errc::malformed, "base64 length is not a multiple of 4");
  }
  Bytes out;
  out.reserve(text.size() / 4 * 3);
  for (std::size_t i = 0; i < text.size(); i += 4) {
    std::uint32_t chunk = 0;
    std::size_t pad = 0;
    for (std::size_t k = 0; k < 4; ++k) {
      const char c = text[i + k];
      const bool last_group = i + 4 == text.size();
      if (c == '=' && last_group && k >= 2 && (k == 3 || text[i + 3] == '=')) {
        ++pad;
        chunk <<= 6U;
        continue;
      }
      const int v = base64_value(c);
      if (v < 0 || pad > 0) {
        return make_error(Errc::malformed, fmt::format("invalid base64 character at {}", i + k));
      }
      chunk = (chunk << 6U) | static_cast<std::uint32_t>(v);
    }
    out.push_back(static_cast<std::uint8_t>(chunk >> 16U));
    if (pad < 2) {
      out.push_back(static_cast<std::uint8_t>(chunk >> 8U));
    }
    if (pad < 1) {
      out.push_back(static_cast<std::uint8_t>(chunk));
    }
  }
  return out;
}

}  // namespace sf::opcua
