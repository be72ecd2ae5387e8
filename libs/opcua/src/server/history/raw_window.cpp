// Raw history reads over values sorted by time (OPC 10000-11 §6.4.3.2) and their stateless
// continuation points (§6.3).
#include <algorithm>
#include <cstring>

#include "sf/core/bytes.hpp"
#include "sf/opcua/server/history.hpp"
#include "sf/opcua/status_codes.hpp"

namespace sf::opcua::server {

namespace {

constexpr std::uint32_t kCursorMagic = 0x31484653;  // "SFH1"

std::int64_t time_of(const DataValue& v) {
  return v.source_timestamp.ticks();
}

std::size_t lower(std::span<const DataValue> sorted, DateTime t) {
  return static_cast<std::size_t>(
      std::lower_bound(sorted.begin(), sorted.end(), t.ticks(),
                       [](const DataValue& v, std::int64_t ticks) { return time_of(v) < ticks; }) -
      sorted.begin());
}

std::size_t upper(std::span<const DataValue> sorted, DateTime t) {
  return static_cast<std::size_t>(
      std::upper_bound(sorted.begin(), sorted.end(), t.ticks(),
                       [](std::int64_t ticks, const DataValue& v) { return ticks < time_of(v); }) -
      sorted.begin());
}

// A bounding value that does not exist (OPC 10000-11 §6.4.3.2: BadBoundNotFound at the bound).
DataValue missing_bound(DateTime at) {
  DataValue v;
  v.status = status::BadBoundNotFound;
  v.source_timestamp = at;
  return v;
}

// Indexes [lo, hi) of the values inside the query's interval, and the direction.
struct Window {
  std::size_t lo = 0;
  std::size_t hi = 0;
  bool forward = true;
};

Window window_of(const HistoryRawQuery& q, std::span<const DataValue> sorted) {
  Window w;
  w.forward = !q.start.is_min() && (q.end.is_min() || q.start <= q.end);
  if (w.forward) {
    w.lo = lower(sorted, q.start);
    w.hi =
        q.end.is_min() ? sorted.size() : (q.start == q.end ? upper(sorted, q.start) : lower(sorted, q.end));
  } else {
    w.lo = q.start.is_min() ? 0 : upper(sorted, q.end);
    w.hi = q.start.is_min() ? upper(sorted, q.end) : upper(sorted, q.start);
  }
  w.hi = std::max(w.hi, w.lo);
  return w;
}

void add_start_bound(const HistoryRawQuery& q, const Window& w, std::span<const DataValue> sorted,
                     std::vector<DataValue>& out) {
  if (q.start.is_min()) {
    return;
  }
  if (w.forward) {
    // The value at the start time is in the data already; else the one before it.
    if (w.lo < sorted.size() && time_of(sorted[w.lo]) == q.start.ticks()) {
      return;
    }
    out.push_back(w.lo > 0 ? sorted[w.lo - 1] : missing_bound(q.start));
  } else {
    if (w.hi > 0 && time_of(sorted[w.hi - 1]) == q.start.ticks()) {
      return;
    }
    out.push_back(w.hi < sorted.size() ? sorted[w.hi] : missing_bound(q.start));
  }
}

void add_end_bound(const HistoryRawQuery& q, const Window& w, std::span<const DataValue> sorted,
                   std::vector<DataValue>& out) {
  if (q.end.is_min()) {
    return;
  }
  if (w.forward) {
    out.push_back(w.hi < sorted.size() ? sorted[w.hi] : missing_bound(q.end));
  } else {
    out.push_back(w.lo > 0 ? sorted[w.lo - 1] : missing_bound(q.end));
  }
}

}  // namespace

ByteString encode_history_cursor(const NodeId& node, const HistoryCursor& cursor) {
  ByteWriter w;
  w.u32(kCursorMagic);
  w.u64(static_cast<std::uint64_t>(node.hash()));
  w.u64(static_cast<std::uint64_t>(cursor.time.ticks()));
  w.u32(cursor.skip);
  return ByteString(w.take());
}

Result<HistoryCursor> decode_history_cursor(const NodeId& node, const ByteString& continuation_point) {
  ByteReader r(continuation_point.span());
  const std::uint32_t magic = r.u32();
  const std::uint64_t owner = r.u64();
  HistoryCursor cursor;
  cursor.time = DateTime(static_cast<std::int64_t>(r.u64()));
  cursor.skip = r.u32();
  if (!r.ok() || r.remaining() != 0 || magic != kCursorMagic ||
      owner != static_cast<std::uint64_t>(node.hash())) {
    return status_error(status::BadContinuationPointInvalid, "not a continuation point of this node");
  }
  return cursor;
}

HistoryRawResult read_raw_sorted(const HistoryRawQuery& query, std::span<const DataValue> sorted) {
  HistoryRawResult result;
  const Window w = window_of(query, sorted);
  // Where this call starts: the window's first value, or after the continuation point's.
  std::size_t begin = w.forward ? w.lo : w.hi;
  const bool first_call = query.continuation_point.is_null() || query.continuation_point.empty();
  if (!first_call) {
    auto cursor = decode_history_cursor(query.node, query.continuation_point);
    if (!cursor) {
      result.status = status::BadContinuationPointInvalid;
      return result;
    }
    begin = w.forward
                ? std::max(w.lo, lower(sorted, cursor->time) + cursor->skip)
                : std::min(w.hi, upper(sorted, cursor->time) - std::min<std::size_t>(cursor->skip, w.hi));
  }
  const std::size_t available =
      w.forward ? (begin < w.hi ? w.hi - begin : 0) : (begin > w.lo ? begin - w.lo : 0);
  const std::size_t take =
      query.max_values == 0 ? available : std::min<std::size_t>(available, query.max_values);
  if (query.return_bounds && first_call) {
    add_start_bound(query, w, sorted, result.values);
  }
  for (std::size_t i = 0; i < take; ++i) {
    result.values.push_back(w.forward ? sorted[begin + i] : sorted[begin - 1 - i]);
  }
  // OPC 10000-11 §6.4.3.2: with one bound open, max_values is the count asked for and no
  // continuation point follows; with both, it pages the interval.
  const bool paged = !query.start.is_min() && !query.end.is_min();
  if (take < available && paged) {
    // The next call continues after the last value returned here.
    const std::size_t last = w.forward ? begin + take - 1 : begin - take;
    const DateTime at(time_of(sorted[last]));
    const std::size_t done_at_time = w.forward ? last + 1 - lower(sorted, at) : upper(sorted, at) - last;
    result.continuation_point =
        encode_history_cursor(query.node, {at, static_cast<std::uint32_t>(done_at_time)});
  } else if (query.return_bounds && take == available) {
    add_end_bound(query, w, sorted, result.values);
  }
  result.status = result.values.empty() ? StatusCode(status::GoodNoData) : StatusCode{};
  return result;
}

}  // namespace sf::opcua::server
