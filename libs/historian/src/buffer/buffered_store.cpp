#include "sf/historian/buffered_store.hpp"

#include <limits>

#include <fmt/format.h>

#include "known_series.hpp"
#include "sf/core/log.hpp"
#include "url.hpp"

namespace sf::historian {

namespace {

// Bytes to read from the buffer for a batch of n samples: about what n
// float samples take (41 bytes each), so a batch is read once, not again and
// again with the rest of the backlog; larger samples make smaller batches.
constexpr std::size_t peek_bytes(std::size_t samples) {
  return samples * 41;
}

bool transient(const Error& e) {
  return e.code == Errc::io;
}

// The leading records of one type that go to the database together, up to
// `max_items` samples (events, series registrations).
std::size_t group_size(std::span<const LogRecord> records, std::size_t max_items,
                       const std::vector<std::size_t>& items) {
  std::size_t n = 1;
  std::size_t total = items[0];
  while (n < records.size() && records[n].type == records.front().type && total + items[n] <= max_items) {
    total += items[n];
    ++n;
  }
  return n;
}

// Items in a samples/events payload without decoding it: the count follows
// the version byte.
std::size_t item_count(const LogRecord& r) {
  if (r.type == RecordType::series || r.payload.size() < 5) {
    return 1;
  }
  return load_le<std::uint32_t>(r.payload.data() + 1);
}

// The items of several records, concatenated in order.
template <typename T>
Result<std::vector<T>> decode_all(std::span<const LogRecord> group,
                                  Result<std::vector<T>> (*decode)(ByteSpan)) {
  std::vector<T> out;
  for (const auto& r : group) {
    auto more = decode(r.payload);
    if (!more) {
      return more.error();
    }
    out.insert(out.end(), std::make_move_iterator(more->begin()), std::make_move_iterator(more->end()));
  }
  return out;
}

}  // namespace

BufferedStore::BufferedStore(Factory factory, BufferOptions options, Clock& clock,
                             std::unique_ptr<SegmentLog> log)
    : factory_(std::move(factory)),
      options_(std::move(options)),
      clock_(clock),
      log_(std::move(log)),
      backoff_(options_.initial_backoff) {
  stats_.recovery = log_->report();
}

Result<std::unique_ptr<BufferedStore>> BufferedStore::open(Factory factory, BufferOptions options,
                                                           Clock& clock) {
  auto log = SegmentLog::open(
      SegmentLogOptions{options.directory, options.segment_bytes, options.fsync, options.on_corruption});
  if (!log) {
    return log.error();
  }
  std::unique_ptr<BufferedStore> store{
      new BufferedStore(std::move(factory), std::move(options), clock, std::move(*log))};
  if (!store->log_->empty()) {
    log::get("historian")
        ->info("store-and-forward buffer {}: {} records to forward", store->options_.directory.string(),
               store->log_->pending_records());
  }
  return store;
}

Result<std::unique_ptr<BufferedStore>> BufferedStore::open(std::string url, BufferOptions options,
                                                           Clock& clock) {
  // A malformed URL will not get better by retrying: refuse it now.
  if (auto parsed = detail::parse_store_url(url); !parsed) {
    return parsed.error();
  }
  return open([url = std::move(url)] { return open_store(url); }, std::move(options), clock);
}

Store* BufferedStore::database(bool ignore_backoff) {
  if (!ignore_backoff && clock_.now() < next_attempt_) {
    return nullptr;
  }
  if (!db_) {
    auto db = factory_();
    if (!db) {
      database_failed(db.error());
      return nullptr;
    }
    db_ = std::move(*db);
  }
  return db_.get();
}

void BufferedStore::database_failed(const Error& error) {
  if (stats_.database_up || stats_.last_error.empty()) {
    log::get("historian")
        ->warn("database unavailable, buffering in {}: {}", options_.directory.string(), error.describe());
  }
  stats_.database_up = false;
  stats_.last_error = error.describe();
  // The next attempt opens the database afresh (new connection, schema
  // check): what comes back may be a restarted server or a restored file.
  db_.reset();
  next_attempt_ = clock_.now() + backoff_;
  backoff_ = std::min(backoff_ * 2, options_.max_backoff);
}

void BufferedStore::database_ok() {
  if (!stats_.database_up && !stats_.last_error.empty()) {
    log::get("historian")->info("database reachable again; {} records buffered", log_->pending_records());
  }
  stats_.database_up = true;
  backoff_ = options_.initial_backoff;
  next_attempt_ = {};
}

Status BufferedStore::buffer(RecordType type, const Bytes& payload, std::uint64_t samples) {
  if (log_->pending_bytes() + payload.size() > options_.max_buffered_bytes) {
    return make_error(Errc::limit_exceeded,
                      fmt::format("store-and-forward buffer {} is full ({} bytes); database: {}",
                                  options_.directory.string(), log_->pending_bytes(), stats_.last_error));
  }
  SF_TRY(log_->append(type, payload));
  stats_.samples_buffered += samples;
  return {};
}

template <typename R, typename F>
std::optional<R> BufferedStore::write_through(F&& write) {
  if (!log_->empty()) {
    return std::nullopt;  // behind what is buffered, never ahead of it
  }
  auto* db = database(false);
  if (db == nullptr) {
    return std::nullopt;
  }
  R result = write(*db);
  if (result) {
    database_ok();
    return result;
  }
  if (!transient(result.error())) {
    return result;  // the caller's mistake: buffering would not help
  }
  database_failed(result.error());
  return std::nullopt;
}

Result<SeriesId> BufferedStore::register_series(const SeriesInfo& info) {
  SF_TRY(detail::validate(info));
  std::lock_guard lock(mutex_);
  registered_[series_id(info.server, info.node_id)] = info;
  if (auto id = write_through<Result<SeriesId>>([&](Store& db) { return db.register_series(info); })) {
    return *id;
  }
  SF_TRY(buffer(RecordType::series, encode_series(info), 0));
  return series_id(info.server, info.node_id);
}

Status BufferedStore::append(std::span<const Sample> samples) {
  if (samples.empty()) {
    return {};
  }
  std::lock_guard lock(mutex_);
  if (auto st = write_through<Status>([&](Store& db) { return db.append(samples); })) {
    return *st;
  }
  return buffer(RecordType::samples, encode_samples(samples), samples.size());
}

Status BufferedStore::append_events(std::span<const Event> events) {
  if (events.empty()) {
    return {};
  }
  std::lock_guard lock(mutex_);
  if (auto st = write_through<Status>([&](Store& db) { return db.append_events(events); })) {
    return *st;
  }
  return buffer(RecordType::events, encode_events(events), 0);
}

Status BufferedStore::poll() {
  std::lock_guard lock(mutex_);
  return forward(options_.forward_per_poll);
}

Status BufferedStore::flush() {
  std::lock_guard lock(mutex_);
  next_attempt_ = {};
  return forward(std::numeric_limits<std::uint64_t>::max());
}

Status BufferedStore::forward(std::uint64_t limit) {
  std::uint64_t sent = 0;
  while (!log_->empty() && sent < limit) {
    auto more = forward_batch(sent);
    if (!more) {
      return more.error();
    }
    if (!*more) {
      break;
    }
  }
  return {};
}

Result<bool> BufferedStore::forward_batch(std::uint64_t& samples_sent) {
  auto* db = database(false);
  if (db == nullptr) {
    return make_error(Errc::io, fmt::format("database unavailable ({} records buffered): {}",
                                            log_->pending_records(), stats_.last_error));
  }
  auto records = log_->peek(peek_bytes(options_.forward_batch));
  if (!records) {
    return records.error();
  }
  if (records->empty()) {
    return false;
  }
  std::vector<std::size_t> items;
  for (const auto& r : *records) {
    items.push_back(item_count(r));
  }
  for (std::size_t max_items = options_.forward_batch;; max_items = 0) {
    const auto n = group_size(*records, max_items, items);
    const std::span<const LogRecord> group{records->data(), n};
    auto sent = send(*db, group);
    if (sent) {
      SF_TRY(log_->consume(group));
      samples_sent += *sent;
      stats_.samples_forwarded += *sent;
      database_ok();
      return true;
    }
    if (transient(sent.error())) {
      database_failed(sent.error());
      return sent.error();
    }
    if (n > 1) {
      continue;  // find the one record the database refuses: again, one at a time
    }
    log::get("historian")
        ->error("store-and-forward: the database refused a buffered record, kept in {}: {}",
                (options_.directory / "rejected.log").string(), sent.error().describe());
    SF_TRY(log_->reject(group));
    SF_TRY(log_->consume(group));
    ++stats_.records_rejected;
    return true;
  }
}

Result<std::uint64_t> BufferedStore::send(Store& db, std::span<const LogRecord> group) {
  switch (group.front().type) {
    case RecordType::series: {
      for (const auto& r : group) {
        auto info = decode_series(r.payload);
        if (!info) {
          return info.error();
        }
        SF_TRY(db.register_series(*info));
      }
      return std::uint64_t{0};
    }
    case RecordType::samples: {
      auto decoded = decode_all(group, decode_samples);
      if (!decoded) {
        return decoded.error();
      }
      const auto& samples = *decoded;
      auto st = db.append(samples);
      if (!st && st.error().code == Errc::not_found && !registered_.empty()) {
        for (const auto& [id, info] : registered_) {
          SF_TRY(db.register_series(info));
        }
        st = db.append(samples);
      }
      return st ? Result<std::uint64_t>{samples.size()} : Result<std::uint64_t>{st.error()};
    }
    case RecordType::events: {
      auto events = decode_all(group, decode_events);
      if (!events) {
        return events.error();
      }
      auto st = db.append_events(*events);
      return st ? Result<std::uint64_t>{0} : Result<std::uint64_t>{st.error()};
    }
  }
  return make_error(Errc::malformed, "unknown buffer record type");
}

template <typename F>
auto BufferedStore::with_database(F&& f) -> decltype(f(std::declval<Store&>())) {
  std::lock_guard lock(mutex_);
  auto* db = database(false);
  if (db == nullptr) {
    return make_error(Errc::io, fmt::format("database unavailable ({} records buffered): {}",
                                            log_->pending_records(), stats_.last_error));
  }
  auto result = f(*db);
  if (!result && transient(result.error())) {
    database_failed(result.error());
  }
  return result;
}

Result<std::vector<Series>> BufferedStore::list_series() {
  return with_database([](Store& db) { return db.list_series(); });
}

Result<std::vector<Sample>> BufferedStore::read_raw(SeriesId series, Timestamp from, Timestamp to,
                                                    std::size_t limit) {
  return with_database([&](Store& db) { return db.read_raw(series, from, to, limit); });
}

Result<std::optional<Sample>> BufferedStore::latest(SeriesId series) {
  return with_database([&](Store& db) { return db.latest(series); });
}

Result<std::vector<AggregateRow>> BufferedStore::aggregate(SeriesId series, Timestamp from, Timestamp to,
                                                           Micros interval, Aggregate which) {
  return with_database([&](Store& db) { return db.aggregate(series, from, to, interval, which); });
}

Result<std::vector<Event>> BufferedStore::read_events(const EventQuery& query) {
  return with_database([&](Store& db) { return db.read_events(query); });
}

Result<RetentionResult> BufferedStore::apply_retention(Timestamp before) {
  return with_database([&](Store& db) { return db.apply_retention(before); });
}

Result<int> BufferedStore::schema_version() {
  return with_database([](Store& db) { return db.schema_version(); });
}

BufferStats BufferedStore::stats() const {
  std::lock_guard lock(mutex_);
  BufferStats s = stats_;
  s.buffered_records = log_->pending_records();
  s.buffered_bytes = log_->pending_bytes();
  return s;
}

}  // namespace sf::historian
