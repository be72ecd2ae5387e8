#include <fmt/format.h>

#include "sf/historian/buffer_records.hpp"

namespace sf::historian {

namespace {

constexpr std::uint8_t kPayloadVersion = 1;
// Smallest encodings, to refuse counts the payload cannot hold before
// reserving memory for them.
constexpr std::size_t kMinSampleBytes = 8 + 8 + 8 + 4 + 4 + 1;
constexpr std::size_t kMinEventBytes = 4 * 7 + 8 + 8 + 2;

void put_string(ByteWriter& w, std::string_view s) {
  w.u32(static_cast<std::uint32_t>(s.size()));
  w.bytes(ByteSpan{reinterpret_cast<const std::uint8_t*>(s.data()), s.size()});
}

void put_bytes(ByteWriter& w, ByteSpan b) {
  w.u32(static_cast<std::uint32_t>(b.size()));
  w.bytes(b);
}

std::string get_string(ByteReader& r) {
  const auto n = r.u32();
  const auto b = r.bytes(n);
  return std::string{reinterpret_cast<const char*>(b.data()), b.size()};
}

Bytes get_bytes(ByteReader& r) {
  const auto n = r.u32();
  const auto b = r.bytes(n);
  return Bytes{b.begin(), b.end()};
}

void put_value(ByteWriter& w, const Value& v) {
  w.u8(static_cast<std::uint8_t>(type_of(v)));
  switch (type_of(v)) {
    case DataType::empty:
      break;
    case DataType::boolean:
      w.u8(std::get<bool>(v) ? 1 : 0);
      break;
    case DataType::int64:
      w.i64(std::get<std::int64_t>(v));
      break;
    case DataType::uint64:
      w.u64(std::get<std::uint64_t>(v));
      break;
    case DataType::float64:
      w.f64(std::get<double>(v));
      break;
    case DataType::string:
      put_string(w, std::get<std::string>(v));
      break;
    case DataType::bytes:
      put_bytes(w, std::get<Bytes>(v));
      break;
  }
}

Value get_value(ByteReader& r) {
  switch (static_cast<DataType>(r.u8())) {
    case DataType::empty:
      return Value{};
    case DataType::boolean:
      return Value{r.u8() != 0};
    case DataType::int64:
      return Value{r.i64()};
    case DataType::uint64:
      return Value{r.u64()};
    case DataType::float64:
      return Value{r.f64()};
    case DataType::string:
      return Value{get_string(r)};
    case DataType::bytes:
      return Value{get_bytes(r)};
  }
  r.fail();
  return Value{};
}

ByteWriter start(Bytes& out) {
  ByteWriter w(out);
  w.u8(kPayloadVersion);
  return w;
}

// Reads the version byte and a count that must fit in what is left.
Result<std::uint32_t> open_payload(ByteReader& r, std::size_t min_item, std::string_view what) {
  const auto version = r.u8();
  if (r.ok() && version != kPayloadVersion) {
    return make_error(Errc::unsupported, fmt::format("{} record of format version {}", what, version));
  }
  const auto count = r.u32();
  if (!r.ok() || count > r.remaining() / min_item) {
    return make_error(Errc::malformed, fmt::format("{} record: count {} does not fit", what, count));
  }
  return count;
}

template <typename T>
Result<T> finish(const ByteReader& r, T value, std::string_view what) {
  if (!r.ok()) {
    return r.error(what);
  }
  if (!r.at_end()) {
    return make_error(Errc::malformed, fmt::format("{} record: {} bytes after the end", what, r.remaining()));
  }
  return value;
}

}  // namespace

Bytes encode_series(const SeriesInfo& info) {
  Bytes out;
  auto w = start(out);
  put_string(w, info.server);
  put_string(w, info.node_id);
  put_string(w, info.browse_path);
  w.u8(static_cast<std::uint8_t>(info.data_type));
  put_string(w, info.unit);
  return out;
}

Bytes encode_samples(std::span<const Sample> samples) {
  Bytes out;
  out.reserve(5 + samples.size() * (kMinSampleBytes + 8));
  auto w = start(out);
  w.u32(static_cast<std::uint32_t>(samples.size()));
  for (const auto& s : samples) {
    w.i64(s.series);
    w.i64(to_micros(s.source_time));
    w.i64(to_micros(s.server_time));
    w.u32(s.seq);
    w.u32(s.status);
    put_value(w, s.value);
  }
  return out;
}

Bytes encode_events(std::span<const Event> events) {
  Bytes out;
  auto w = start(out);
  w.u32(static_cast<std::uint32_t>(events.size()));
  for (const auto& e : events) {
    put_string(w, e.server);
    put_bytes(w, e.event_id);
    w.i64(to_micros(e.time));
    w.i64(to_micros(e.receive_time));
    put_string(w, e.event_type);
    put_string(w, e.source_node);
    put_string(w, e.source_name);
    w.u16(e.severity);
    put_string(w, e.message);
    put_string(w, e.fields);
  }
  return out;
}

Result<SeriesInfo> decode_series(ByteSpan payload) {
  ByteReader r(payload);
  const auto version = r.u8();
  if (r.ok() && version != kPayloadVersion) {
    return make_error(Errc::unsupported, fmt::format("series record of format version {}", version));
  }
  SeriesInfo info;
  info.server = get_string(r);
  info.node_id = get_string(r);
  info.browse_path = get_string(r);
  info.data_type = static_cast<DataType>(r.u8());
  info.unit = get_string(r);
  return finish(r, std::move(info), "series");
}

namespace {

// A count of items, each read by read_one, and nothing after them.
template <typename T, typename F>
Result<std::vector<T>> decode_list(ByteSpan payload, std::size_t min_item, std::string_view what,
                                   F read_one) {
  ByteReader r(payload);
  auto count = open_payload(r, min_item, what);
  if (!count) {
    return count.error();
  }
  std::vector<T> out;
  out.reserve(*count);
  for (std::uint32_t i = 0; i < *count && r.ok(); ++i) {
    out.push_back(read_one(r));
  }
  return finish(r, std::move(out), what);
}

}  // namespace

Result<std::vector<Sample>> decode_samples(ByteSpan payload) {
  return decode_list<Sample>(payload, kMinSampleBytes, "samples", [](ByteReader& r) {
    Sample s;
    s.series = r.i64();
    s.source_time = from_micros(r.i64());
    s.server_time = from_micros(r.i64());
    s.seq = r.u32();
    s.status = r.u32();
    s.value = get_value(r);
    return s;
  });
}

Result<std::vector<Event>> decode_events(ByteSpan payload) {
  return decode_list<Event>(payload, kMinEventBytes, "events", [](ByteReader& r) {
    Event e;
    e.server = get_string(r);
    e.event_id = get_bytes(r);
    e.time = from_micros(r.i64());
    e.receive_time = from_micros(r.i64());
    e.event_type = get_string(r);
    e.source_node = get_string(r);
    e.source_name = get_string(r);
    e.severity = r.u16();
    e.message = get_string(r);
    e.fields = get_string(r);
    return e;
  });
}

}  // namespace sf::historian
