// What the historian stores: a registry of series (one per OPC UA variable
// of one server), samples of those series and events. Paper §V.B (Fig. 6):
// the cloud, an OPC UA client of every shop-floor server, delivers historical
// data and events to the database. The types mirror an OPC UA DataValue
// (value, StatusCode, source and server timestamps; Part 4 §7.11) without
// depending on the OPC UA module: the gateway maps one onto the other.
#pragma once

#include <chrono>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include "sf/core/bytes.hpp"

namespace sf::historian {

// Microseconds since the Unix epoch (UTC). OPC UA DateTime has 100 ns ticks;
// PostgreSQL timestamps and most plant data are good to 1 µs, and an int64 of
// microseconds covers ±292 000 years, so both back ends store it as int64.
using Micros = std::chrono::microseconds;
using Timestamp = std::chrono::sys_time<Micros>;

[[nodiscard]] inline std::int64_t to_micros(Timestamp t) {
  return t.time_since_epoch().count();
}
[[nodiscard]] inline Timestamp from_micros(std::int64_t us) {
  return Timestamp{Micros{us}};
}

// A series' id is derived from its key (server, node id) — see series_id() —
// so it is the same in every database and can be handed out while the
// database is unreachable (store-and-forward registers series offline).
using SeriesId = std::int64_t;

// The value types a sample can hold. OPC UA's integer widths collapse onto
// int64/uint64, Float onto float64; `empty` is a DataValue without a value
// (typically with a Bad status).
enum class DataType : std::uint8_t { empty = 0, boolean, int64, uint64, float64, string, bytes };

using Value = std::variant<std::monostate, bool, std::int64_t, std::uint64_t, double, std::string, Bytes>;

[[nodiscard]] DataType type_of(const Value& v);
[[nodiscard]] std::string_view to_string(DataType t);
// "boolean", "int64", ... (as printed by to_string); unknown names → nullopt.
[[nodiscard]] std::optional<DataType> data_type_from_string(std::string_view name);
// The value as a number for aggregates: booleans 0/1, integers, floats;
// nullopt for strings, bytes and empty values.
[[nodiscard]] std::optional<double> numeric(const Value& v);
// Human-readable, for the CLI and test messages: 3.25, true, "text", 0x01ff.
[[nodiscard]] std::string format_value(const Value& v);

// OPC UA StatusCode (Part 4 §7.34): the top two bits give the severity.
using StatusCode = std::uint32_t;
inline constexpr StatusCode kGood = 0;
[[nodiscard]] inline bool is_bad(StatusCode s) {
  return (s >> 30U) == 2U;
}

// One series: an OPC UA variable of one server. (server, node_id) is the key;
// the rest describes it and may change when re-registered.
struct SeriesInfo {
  std::string server{};       // the server's endpoint URL or ApplicationUri
  std::string node_id{};      // NodeId in its string form, e.g. "ns=2;s=Line1.Temp"
  std::string browse_path{};  // e.g. "/Objects/Line1/Oven/Temperature"; what people search by
  DataType data_type = DataType::float64;
  std::string unit{};  // EngineeringUnits display name, e.g. "°C"
  bool operator==(const SeriesInfo&) const = default;
};

struct Series {
  SeriesId id = 0;
  SeriesInfo info{};
  bool operator==(const Series&) const = default;
};

// The id of the series (server, node_id): 63 bits of a 64-bit FNV-1a hash of
// both strings, never 0. With a million series the chance of any collision is
// about 3e-8; a store refuses to register a colliding key with a clear error.
[[nodiscard]] SeriesId series_id(std::string_view server, std::string_view node_id);

// One value of one series: an OPC UA DataValue. Samples are keyed by
// (series, source_time, seq); writing the same key again is a no-op (the
// first write wins), which is what makes re-delivery after a failure safe.
// `seq` tells apart samples of one series that carry the same source
// timestamp (the gateway numbers them); it is 0 otherwise.
struct Sample {
  SeriesId series = 0;
  Timestamp source_time{};
  Timestamp server_time{};
  std::uint32_t seq = 0;
  StatusCode status = kGood;
  Value value{};
  bool operator==(const Sample&) const = default;
};

// An OPC UA event (BaseEventType fields, Part 5 §6.4.2). (server, event_id,
// time) is the key; re-delivery of the same event is a no-op.
struct Event {
  std::string server{};
  Bytes event_id{};  // EventId: unique per server
  Timestamp time{};
  Timestamp receive_time{};
  std::string event_type{};   // NodeId of the event type
  std::string source_node{};  // NodeId of the source
  std::string source_name{};
  std::uint16_t severity = 0;  // 1..1000
  std::string message{};
  std::string fields{};  // further selected fields, JSON text chosen by the gateway
  bool operator==(const Event&) const = default;
};

struct EventQuery {
  Timestamp from{};
  Timestamp to{};
  std::optional<std::string> server{};  // all servers when empty
  std::size_t limit = 10'000;
};

// Aggregates over [start, start + interval): min/max/avg over numeric values,
// count of samples; samples with a Bad status are left out (as OPC UA's
// Part 13 aggregates use good data only).
enum class Aggregate : unsigned { min = 1, max = 2, avg = 4, count = 8, all = 15 };
[[nodiscard]] constexpr Aggregate operator|(Aggregate a, Aggregate b) {
  return static_cast<Aggregate>(static_cast<unsigned>(a) | static_cast<unsigned>(b));
}
[[nodiscard]] constexpr bool has(Aggregate set, Aggregate one) {
  return (static_cast<unsigned>(set) & static_cast<unsigned>(one)) != 0;
}

struct AggregateRow {
  Timestamp start{};
  std::optional<std::uint64_t> count{};
  std::optional<double> min{};
  std::optional<double> max{};
  std::optional<double> avg{};
  bool operator==(const AggregateRow&) const = default;
};

struct RetentionResult {
  std::uint64_t samples_deleted = 0;  // rows deleted one by one
  std::uint64_t events_deleted = 0;
  std::uint64_t partitions_dropped = 0;  // whole time partitions dropped (PostgreSQL)
};

}  // namespace sf::historian
