// SQLite back end. One connection in WAL mode (readers such as the CLI do
// not block the writer and vice versa), a batch per BEGIN IMMEDIATE
// transaction, statements prepared once, and the busy timeout as the only
// waiting: a database locked longer than that reports Errc::io, which is
// BufferedStore's signal to buffer.
#include "sqlite/sqlite_store.hpp"

#include <algorithm>
#include <charconv>
#include <limits>

#include <fmt/format.h>

#include "known_series.hpp"
#include "sqlite/sqlite_db.hpp"
#include "sqlite/sqlite_schema.hpp"
#include "value_columns.hpp"

namespace sf::historian::sqlite {

namespace {

constexpr std::string_view kSampleColumns =
    "source_time, seq, server_time, status, vtype, v_int, v_real, v_text, v_blob";
constexpr std::string_view kEventColumns =
    "server, event_id, time, receive_time, event_type, source_node, source_name, severity, message, fields";

struct Statements {
  Statement get_series, upsert_series, list_series, insert_sample, insert_event;
  Statement read_raw, latest, aggregate, read_events, delete_samples, delete_events;
};

Result<Statements> prepare_all(Db& db) {
  Statements s;
  const std::pair<Statement*, std::string> sql[] = {
      {&s.get_series, "SELECT server, node_id, browse_path, data_type, unit FROM series WHERE id = ?1"},
      {&s.upsert_series,
       "INSERT INTO series (id, server, node_id, browse_path, data_type, unit) VALUES (?1, ?2, ?3, ?4, ?5, "
       "?6) "
       "ON CONFLICT (id) DO UPDATE SET browse_path = excluded.browse_path, data_type = excluded.data_type, "
       "unit = excluded.unit"},
      {&s.list_series,
       "SELECT id, server, node_id, browse_path, data_type, unit FROM series "
       "ORDER BY browse_path, server, node_id"},
      {&s.insert_sample,
       fmt::format("INSERT INTO samples (series_id, {}) VALUES (?1, ?2, ?3, ?4, ?5, ?6, ?7, "
                   "?8, ?9, ?10) ON CONFLICT DO NOTHING",
                   kSampleColumns)},
      {&s.insert_event,
       fmt::format("INSERT INTO events ({}) VALUES (?1, ?2, ?3, ?4, ?5, ?6, ?7, ?8, ?9, ?10) "
                   "ON CONFLICT DO NOTHING",
                   kEventColumns)},
      {&s.read_raw, fmt::format("SELECT {} FROM samples WHERE series_id = ?1 AND source_time >= ?2 AND "
                                "source_time < ?3 ORDER BY source_time, seq LIMIT ?4",
                                kSampleColumns)},
      {&s.latest, fmt::format("SELECT {} FROM samples WHERE series_id = ?1 "
                              "ORDER BY source_time DESC, seq DESC LIMIT 1",
                              kSampleColumns)},
      {&s.aggregate, fmt::format("SELECT (source_time - ?2) / ?4 AS bucket, count(*), min(x), max(x), avg(x) "
                                 "FROM (SELECT source_time, {} AS x FROM samples WHERE series_id = ?1 AND "
                                 "source_time >= ?2 AND source_time < ?3 AND (status >> 30) <> 2) "
                                 "GROUP BY bucket ORDER BY bucket",
                                 detail::numeric_sql("REAL", "v_real"))},
      {&s.read_events, fmt::format("SELECT {} FROM events WHERE time >= ?1 AND time < ?2 AND "
                                   "(?3 IS NULL OR server = ?3) ORDER BY time, server, event_id LIMIT ?4",
                                   kEventColumns)},
      {&s.delete_samples, "DELETE FROM samples WHERE source_time < ?1"},
      {&s.delete_events, "DELETE FROM events WHERE time < ?1"},
  };
  for (const auto& [stmt, text] : sql) {
    auto prepared = db.prepare(text);
    if (!prepared) {
      return prepared.error();
    }
    *stmt = std::move(*prepared);
  }
  return s;
}

// Resets a statement when the operation using it ends, however it ends.
class Use {
 public:
  explicit Use(Statement& s) : s_(s) {}
  ~Use() { s_.reset(); }
  Use(const Use&) = delete;
  Use& operator=(const Use&) = delete;
  Statement* operator->() { return &s_; }

 private:
  Statement& s_;
};

std::int64_t clamp_limit(std::size_t limit) {
  return static_cast<std::int64_t>(std::min<std::size_t>(limit, std::numeric_limits<std::int64_t>::max()));
}

Result<Sample> sample_from_row(const Statement& s, SeriesId series) {
  detail::ValueColumns c{static_cast<int>(s.int64(4)), s.opt_int64(5), s.opt_real(6), s.opt_text(7),
                         s.opt_blob(8)};
  auto value = detail::from_columns(std::move(c));
  if (!value) {
    return value.error();
  }
  return Sample{series,
                from_micros(s.int64(0)),
                from_micros(s.int64(2)),
                static_cast<std::uint32_t>(s.int64(1)),
                static_cast<StatusCode>(s.int64(3)),
                std::move(*value)};
}

Event event_from_row(const Statement& s) {
  return Event{s.text(0),
               s.blob(1),
               from_micros(s.int64(2)),
               from_micros(s.int64(3)),
               s.text(4),
               s.text(5),
               s.text(6),
               static_cast<std::uint16_t>(s.int64(7)),
               s.text(8),
               s.text(9)};
}

Result<int> parse_int_param(const detail::StoreUrl& url, const std::string& key, int fallback) {
  const auto it = url.params.find(key);
  if (it == url.params.end()) {
    return fallback;
  }
  int value = 0;
  const auto* end = it->second.data() + it->second.size();
  const auto [p, ec] = std::from_chars(it->second.data(), end, value);
  if (ec != std::errc{} || p != end || value < 0) {
    return make_error(Errc::invalid_argument, fmt::format("sqlite:{}: {}={} is not a non-negative integer",
                                                          url.target, key, it->second));
  }
  return value;
}

class SqliteStore final : public Store {
 public:
  SqliteStore(Db db, Statements stmts, std::string path)
      : db_(std::move(db)), s_(std::move(stmts)), path_(std::move(path)) {}

  Result<SeriesId> register_series(const SeriesInfo& info) override;
  Result<std::vector<Series>> list_series() override;
  Status append(std::span<const Sample> samples) override;
  Status append_events(std::span<const Event> events) override;
  Result<std::vector<Sample>> read_raw(SeriesId series, Timestamp from, Timestamp to,
                                       std::size_t limit) override;
  Result<std::optional<Sample>> latest(SeriesId series) override;
  Result<std::vector<AggregateRow>> aggregate(SeriesId series, Timestamp from, Timestamp to, Micros interval,
                                              Aggregate which) override;
  Result<std::vector<Event>> read_events(const EventQuery& query) override;
  Result<RetentionResult> apply_retention(Timestamp before) override;
  Result<int> schema_version() override { return sqlite::schema_version(db_); }
  [[nodiscard]] std::string_view backend() const override { return "sqlite"; }

 private:
  Result<std::optional<SeriesInfo>> find_series(SeriesId id);
  Error context(const Error& e, std::string_view what) const {
    return e.with_context(fmt::format("{} ({})", what, path_));
  }

  Db db_;
  Statements s_;
  std::string path_;
  detail::KnownSeries known_;
};

Result<std::optional<SeriesInfo>> SqliteStore::find_series(SeriesId id) {
  Use q(s_.get_series);
  q->bind(1, id);
  auto row = q->step();
  if (!row) {
    return row.error();
  }
  if (!*row) {
    return std::optional<SeriesInfo>{};
  }
  return std::optional<SeriesInfo>{
      SeriesInfo{q->text(0), q->text(1), q->text(2), static_cast<DataType>(q->int64(3)), q->text(4)}};
}

Result<SeriesId> SqliteStore::register_series(const SeriesInfo& info) {
  SF_TRY(detail::validate(info));
  const SeriesId id = series_id(info.server, info.node_id);
  auto existing = find_series(id);
  if (!existing) {
    return context(existing.error(), "register series");
  }
  if (*existing && ((*existing)->server != info.server || (*existing)->node_id != info.node_id)) {
    return detail::collision(info, **existing);
  }
  Use q(s_.upsert_series);
  q->bind(1, id).bind(2, info.server).bind(3, info.node_id).bind(4, info.browse_path);
  q->bind(5, std::int64_t{static_cast<int>(info.data_type)}).bind(6, info.unit);
  if (auto st = q->run(); !st) {
    return context(st.error(), "register series");
  }
  known_.add(id);
  return id;
}

Result<std::vector<Series>> SqliteStore::list_series() {
  Use q(s_.list_series);
  std::vector<Series> out;
  auto st = q->for_each_row([&]() -> Status {
    out.push_back(Series{q->int64(0), SeriesInfo{q->text(1), q->text(2), q->text(3),
                                                 static_cast<DataType>(q->int64(4)), q->text(5)}});
    return {};
  });
  return st ? Result<std::vector<Series>>{std::move(out)} : context(st.error(), "list series");
}

Status SqliteStore::append(std::span<const Sample> samples) {
  auto lookup = [&](SeriesId id) -> Result<bool> {
    auto found = find_series(id);
    return found ? Result<bool>{found->has_value()} : Result<bool>{found.error()};
  };
  SF_TRY(known_.check(samples, lookup));
  Transaction tx(db_);
  if (auto st = tx.begin(); !st) {
    return context(st.error(), fmt::format("append {} samples", samples.size()));
  }
  for (const auto& s : samples) {
    const auto c = detail::to_columns(s.value);
    Use q(s_.insert_sample);
    q->bind(1, s.series).bind(2, to_micros(s.source_time)).bind(3, std::int64_t{s.seq});
    q->bind(4, to_micros(s.server_time)).bind(5, std::int64_t{s.status}).bind(6, std::int64_t{c.vtype});
    q->bind(7, c.v_int).bind(8, c.v_real).bind(9, c.v_text);
    c.v_blob ? q->bind(10, ByteSpan{*c.v_blob}) : q->bind_null(10);
    if (auto st = q->run(); !st) {
      return context(st.error(), fmt::format("append {} samples", samples.size()));
    }
  }
  if (auto st = tx.commit(); !st) {
    return context(st.error(), fmt::format("append {} samples", samples.size()));
  }
  return {};
}

Status SqliteStore::append_events(std::span<const Event> events) {
  Transaction tx(db_);
  if (auto st = tx.begin(); !st) {
    return context(st.error(), fmt::format("append {} events", events.size()));
  }
  for (const auto& e : events) {
    Use q(s_.insert_event);
    q->bind(1, e.server).bind(2, ByteSpan{e.event_id}).bind(3, to_micros(e.time));
    q->bind(4, to_micros(e.receive_time)).bind(5, e.event_type).bind(6, e.source_node);
    q->bind(7, e.source_name).bind(8, std::int64_t{e.severity}).bind(9, e.message).bind(10, e.fields);
    if (auto st = q->run(); !st) {
      return context(st.error(), fmt::format("append {} events", events.size()));
    }
  }
  if (auto st = tx.commit(); !st) {
    return context(st.error(), fmt::format("append {} events", events.size()));
  }
  return {};
}

Result<std::vector<Sample>> SqliteStore::read_raw(SeriesId series, Timestamp from, Timestamp to,
                                                  std::size_t limit) {
  Use q(s_.read_raw);
  q->bind(1, series).bind(2, to_micros(from)).bind(3, to_micros(to)).bind(4, clamp_limit(limit));
  std::vector<Sample> out;
  auto st = q->for_each_row([&]() -> Status {
    auto sample = sample_from_row(*q.operator->(), series);
    if (!sample) {
      return sample.error();
    }
    out.push_back(std::move(*sample));
    return {};
  });
  return st ? Result<std::vector<Sample>>{std::move(out)} : context(st.error(), "read samples");
}

Result<std::optional<Sample>> SqliteStore::latest(SeriesId series) {
  Use q(s_.latest);
  q->bind(1, series);
  auto row = q->step();
  if (!row) {
    return context(row.error(), "latest sample");
  }
  if (!*row) {
    return std::optional<Sample>{};
  }
  auto sample = sample_from_row(*q.operator->(), series);
  if (!sample) {
    return context(sample.error(), "latest sample");
  }
  return std::optional<Sample>{std::move(*sample)};
}

Result<std::vector<AggregateRow>> SqliteStore::aggregate(SeriesId series, Timestamp from, Timestamp to,
                                                         Micros interval, Aggregate which) {
  if (interval.count() <= 0) {
    return make_error(Errc::invalid_argument, "aggregate interval must be positive");
  }
  Use q(s_.aggregate);
  q->bind(1, series).bind(2, to_micros(from)).bind(3, to_micros(to)).bind(4, std::int64_t{interval.count()});
  std::vector<AggregateRow> out;
  auto st = q->for_each_row([&]() -> Status {
    AggregateRow r;
    r.start = from + q->int64(0) * interval;
    if (has(which, Aggregate::count)) {
      r.count = static_cast<std::uint64_t>(q->int64(1));
    }
    if (has(which, Aggregate::min)) {
      r.min = q->opt_real(2);
    }
    if (has(which, Aggregate::max)) {
      r.max = q->opt_real(3);
    }
    if (has(which, Aggregate::avg)) {
      r.avg = q->opt_real(4);
    }
    out.push_back(r);
    return {};
  });
  return st ? Result<std::vector<AggregateRow>>{std::move(out)} : context(st.error(), "aggregate");
}

Result<std::vector<Event>> SqliteStore::read_events(const EventQuery& query) {
  Use q(s_.read_events);
  q->bind(1, to_micros(query.from)).bind(2, to_micros(query.to)).bind(3, query.server);
  q->bind(4, clamp_limit(query.limit));
  std::vector<Event> out;
  auto st = q->for_each_row([&]() -> Status {
    out.push_back(event_from_row(*q.operator->()));
    return {};
  });
  return st ? Result<std::vector<Event>>{std::move(out)} : context(st.error(), "read events");
}

Result<RetentionResult> SqliteStore::apply_retention(Timestamp before) {
  RetentionResult result;
  Transaction tx(db_);
  SF_TRY(tx.begin());
  {
    Use q(s_.delete_samples);
    q->bind(1, to_micros(before));
    SF_TRY(q->run());
    result.samples_deleted = static_cast<std::uint64_t>(db_.changes());
  }
  {
    Use q(s_.delete_events);
    q->bind(1, to_micros(before));
    SF_TRY(q->run());
    result.events_deleted = static_cast<std::uint64_t>(db_.changes());
  }
  SF_TRY(tx.commit());
  return result;
}

Status configure(Db& db, const detail::StoreUrl& url) {
  auto busy_ms = parse_int_param(url, "busy_timeout_ms", 5000);
  if (!busy_ms) {
    return busy_ms.error();
  }
  sqlite3_busy_timeout(db.handle(), *busy_ms);
  std::string sync = "NORMAL";
  if (const auto it = url.params.find("synchronous"); it != url.params.end()) {
    if (it->second != "normal" && it->second != "full") {
      return make_error(Errc::invalid_argument,
                        fmt::format("sqlite:{}: synchronous={} (normal or full)", url.target, it->second));
    }
    sync = it->second == "full" ? "FULL" : "NORMAL";
  }
  // WAL: one writer and any number of readers at once; with synchronous=NORMAL
  // a commit is durable against a process crash (not a power cut — use
  // synchronous=full for that) and needs no fsync per transaction.
  auto mode = db.query_text("PRAGMA journal_mode = WAL");
  if (!mode) {
    return mode.error();
  }
  if (*mode != "wal" && *mode != "memory") {
    return make_error(Errc::io, fmt::format("sqlite:{}: cannot switch to WAL mode (journal_mode is {})",
                                            url.target, *mode));
  }
  // Checkpoints every 10 000 WAL pages (40 MB) rather than 1 000: a batch of
  // samples spread over many series touches a page per series, and each
  // checkpoint copies those pages back and syncs; measured 1.3x the ingest
  // rate with batches of 1 000 (bench_historian_ingest).
  // A 64 MiB page cache instead of SQLite's 2 MiB: with thousands of series every batch touches
  // index pages of all of them, and a small cache re-reads (and copies) each from the OS per
  // batch; measured 62 500 → see docs/performance.md (bench_cloud_latency, 10 000 series).
  return db.exec(
      fmt::format("PRAGMA synchronous = {}; PRAGMA foreign_keys = ON; PRAGMA wal_autocheckpoint = 10000; "
                  "PRAGMA cache_size = -65536",
                  sync));
}

}  // namespace

Result<std::unique_ptr<Store>> open_store(const detail::StoreUrl& url, const StoreOptions& options) {
  auto db = Db::open(url.target);
  if (!db) {
    return db.error();
  }
  SF_TRY(configure(*db, url));
  if (auto st = migrate(*db, options.schema_target); !st) {
    return st.error().with_context(url.target);
  }
  auto stmts = prepare_all(*db);
  if (!stmts) {
    return stmts.error();
  }
  return std::unique_ptr<Store>{std::make_unique<SqliteStore>(std::move(*db), std::move(*stmts), url.target)};
}

}  // namespace sf::historian::sqlite
