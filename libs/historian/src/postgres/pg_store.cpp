// PostgreSQL back end over libpqxx 6.4. A batch is COPYed into its table
// (PostgreSQL's fastest way in); when that fails because some keys are
// stored already (a re-delivered batch), it is COPYed into a temporary
// staging table and moved with one INSERT ... SELECT ... ON CONFLICT DO
// NOTHING, which makes the re-delivered rows no-ops (COPY has no ON CONFLICT). Samples and
// events live in time-partitioned tables (pg_schema.hpp). Reads use prepared
// statements. The connection comes back by itself after the server does.
#include "postgres/pg_store.hpp"

#include <vector>

#include <fmt/format.h>

#include "known_series.hpp"
#include "postgres/pg_connection.hpp"
#include "postgres/pg_schema.hpp"
#include "value_columns.hpp"

namespace sf::historian::postgres {

namespace {

// Column lists for COPY (function-local statics: built on first use).
const std::vector<std::string>& sample_columns() {
  static const std::vector<std::string> columns = {"series_id", "source_time", "seq",   "server_time",
                                                   "status",    "vtype",       "v_int", "v_real",
                                                   "v_text",    "v_blob"};
  return columns;
}

const std::vector<std::string>& event_columns() {
  static const std::vector<std::string> columns = {"server",     "event_id",    "time",        "receive_time",
                                                   "event_type", "source_node", "source_name", "severity",
                                                   "message",    "fields"};
  return columns;
}

constexpr std::string_view kSampleRead =
    "source_time, seq, server_time, status, vtype, v_int, v_real, v_text, v_blob";
constexpr std::string_view kEventRead =
    "server, event_id, time, receive_time, event_type, source_node, source_name, severity, message, fields";

// Session settings and the staging tables; run on every new connection.
void setup_session(pqxx::connection& c) {
  pqxx::nontransaction tx(c);
  // CREATE ... IF NOT EXISTS reports NOTICEs that libpq would print on stderr.
  tx.exec("SET client_min_messages TO warning");
  tx.exec(
      "CREATE TEMP TABLE IF NOT EXISTS sf_staging_samples (series_id bigint, source_time bigint, seq bigint, "
      "server_time bigint, status bigint, vtype smallint, v_int bigint, v_real double precision, v_text "
      "text, "
      "v_blob bytea) ON COMMIT DELETE ROWS");
  tx.exec(
      "CREATE TEMP TABLE IF NOT EXISTS sf_staging_events (server text, event_id bytea, time bigint, "
      "receive_time bigint, event_type text, source_node text, source_name text, severity integer, "
      "message text, fields text) ON COMMIT DELETE ROWS");
}

// Statements that name the schema's tables; prepared once the schema exists.
void prepare_statements(pqxx::connection& c) {
  c.prepare("get_series", "SELECT server, node_id, browse_path, data_type, unit FROM series WHERE id = $1");
  c.prepare(
      "upsert_series",
      "INSERT INTO series (id, server, node_id, browse_path, data_type, unit) VALUES ($1, $2, $3, $4, $5, "
      "$6) "
      "ON CONFLICT (id) DO UPDATE SET browse_path = excluded.browse_path, data_type = excluded.data_type, "
      "unit = excluded.unit");
  c.prepare("list_series",
            "SELECT id, server, node_id, browse_path, data_type, unit FROM series "
            "ORDER BY browse_path, server, node_id");
  c.prepare("read_raw", fmt::format("SELECT {} FROM samples WHERE series_id = $1 AND source_time >= $2 AND "
                                    "source_time < $3 ORDER BY source_time, seq LIMIT $4",
                                    kSampleRead));
  c.prepare("latest", fmt::format("SELECT {} FROM samples WHERE series_id = $1 "
                                  "ORDER BY source_time DESC, seq DESC LIMIT 1",
                                  kSampleRead));
  c.prepare(
      "aggregate",
      fmt::format("SELECT (source_time - $2) / $4 AS bucket, count(*), min(x), max(x), avg(x) FROM "
                  "(SELECT source_time, {} AS x FROM samples WHERE series_id = $1 AND source_time >= $2 "
                  "AND source_time < $3 AND (status >> 30) <> 2) s GROUP BY bucket ORDER BY bucket",
                  detail::numeric_sql("float8", "NULLIF(v_real, 'NaN'::float8)")));
  c.prepare("read_events",
            fmt::format("SELECT {} FROM events WHERE time >= $1 AND time < $2 AND "
                        "($3::text IS NULL OR server = $3) ORDER BY time, server, event_id LIMIT $4",
                        kEventRead));
}

Sample sample_from_row(const pqxx::row& r, SeriesId series, Value value) {
  return Sample{series,
                from_micros(as_int64(r[0])),
                from_micros(as_int64(r[2])),
                static_cast<std::uint32_t>(as_int64(r[1])),
                static_cast<StatusCode>(as_int64(r[3])),
                std::move(value)};
}

Result<Value> value_from_row(const pqxx::row& r) {
  return detail::from_columns(detail::ValueColumns{static_cast<int>(as_int64(r[4])), as_opt_int64(r[5]),
                                                   as_opt_double(r[6]), as_opt_text(r[7]),
                                                   as_opt_bytes(r[8])});
}

Result<std::vector<Sample>> samples_from(const pqxx::result& rows, SeriesId series) {
  std::vector<Sample> out;
  out.reserve(rows.size());
  for (const auto& r : rows) {
    auto value = value_from_row(r);
    if (!value) {
      return value.error();
    }
    out.push_back(sample_from_row(r, series, std::move(*value)));
  }
  return out;
}

std::int64_t clamp_limit(std::size_t limit) {
  return static_cast<std::int64_t>(std::min<std::size_t>(limit, std::numeric_limits<std::int64_t>::max()));
}

class PgStore final : public Store {
 public:
  PgStore(std::string conninfo, std::string redacted)
      : conn_(std::move(conninfo), std::move(redacted), [this](pqxx::connection& c) { on_connect(c); }) {}

  Status open(const StoreOptions& options);

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
  Result<int> schema_version() override {
    return conn_.run("schema version", [](pqxx::connection& c) { return postgres::schema_version(c); });
  }
  [[nodiscard]] std::string_view backend() const override { return "postgresql"; }

 private:
  void on_connect(pqxx::connection& c) const {
    setup_session(c);
    if (schema_ready_) {
      prepare_statements(c);
    }
  }
  Result<std::optional<SeriesInfo>> find_series(SeriesId id);
  // COPY into staging, then INSERT ... ON CONFLICT DO NOTHING; one transaction.
  template <typename Row, typename Item>
  void copy_in(pqxx::connection& c, std::string_view table, const std::vector<std::string>& columns,
               std::span<const Item> items, Row row);
  // Runs `write` with the partitions for `times` in place; when another
  // program dropped one we thought existed (retention), once more.
  void with_partitions(pqxx::connection& c, Partitions& parts, std::span<const std::int64_t> times,
                       const std::function<void()>& write);

  Connection conn_;
  bool schema_ready_ = false;
  Partitions sample_parts_{"samples", std::chrono::hours{24}};
  Partitions event_parts_{"events", std::chrono::hours{24}};
  detail::KnownSeries known_;
};

Status PgStore::open(const StoreOptions& options) {
  SF_TRY(conn_.run("create schema_migrations", [](pqxx::connection& c) { bootstrap_migrations(c); }));
  const detail::MigrationTarget target{
      "postgresql",
      [&] {
        return conn_.run("schema version", [](pqxx::connection& c) { return postgres::schema_version(c); });
      },
      [&](const detail::Migration& m) {
        return conn_.run("migrate", [&](pqxx::connection& c) { apply_migration(c, m); });
      }};
  SF_TRY(detail::run_migrations(migrations(), target, options.schema_target));
  auto width = conn_.run("partition width", [&](pqxx::connection& c) {
    schema_ready_ = true;
    prepare_statements(c);
    return partition_width(c, options.partition_width);
  });
  if (!width) {
    return width.error();
  }
  sample_parts_ = Partitions{"samples", *width};
  event_parts_ = Partitions{"events", *width};
  return {};
}

Result<std::optional<SeriesInfo>> PgStore::find_series(SeriesId id) {
  return conn_.run("find series", [&](pqxx::connection& c) -> std::optional<SeriesInfo> {
    pqxx::nontransaction tx(c);
    const auto rows = tx.exec_prepared("get_series", id);
    if (rows.empty()) {
      return std::nullopt;
    }
    const auto& r = rows[0];
    return SeriesInfo{r[0].c_str(), r[1].c_str(), r[2].c_str(), static_cast<DataType>(as_int64(r[3])),
                      r[4].c_str()};
  });
}

Result<SeriesId> PgStore::register_series(const SeriesInfo& info) {
  SF_TRY(detail::validate(info));
  const SeriesId id = series_id(info.server, info.node_id);
  auto existing = find_series(id);
  if (!existing) {
    return existing.error();
  }
  if (*existing && ((*existing)->server != info.server || (*existing)->node_id != info.node_id)) {
    return detail::collision(info, **existing);
  }
  SF_TRY(conn_.run("register series", [&](pqxx::connection& c) {
    pqxx::work tx(c);
    tx.exec_prepared("upsert_series", id, info.server, info.node_id, info.browse_path,
                     static_cast<int>(info.data_type), info.unit);
    tx.commit();
  }));
  known_.add(id);
  return id;
}

Result<std::vector<Series>> PgStore::list_series() {
  return conn_.run("list series", [](pqxx::connection& c) {
    pqxx::nontransaction tx(c);
    std::vector<Series> out;
    for (const auto& r : tx.exec_prepared("list_series")) {
      out.push_back(Series{as_int64(r[0]), SeriesInfo{r[1].c_str(), r[2].c_str(), r[3].c_str(),
                                                      static_cast<DataType>(as_int64(r[4])), r[5].c_str()}});
    }
    return out;
  });
}

template <typename Row, typename Item>
void PgStore::copy_in(pqxx::connection& c, std::string_view table, const std::vector<std::string>& columns,
                      std::span<const Item> items, Row row) {
  const auto stream = [&](pqxx::work& tx, const std::string& target) {
    pqxx::stream_to copy(tx, target, columns);
    for (const auto& item : items) {
      copy << row(item);
    }
    copy.complete();
  };
  // Usually every row is new: COPY straight into the table, as fast as
  // PostgreSQL loads anything. COPY is all or nothing, so a key stored
  // already (a batch sent again after a failure) fails the whole batch...
  try {
    pqxx::work tx(c);
    stream(tx, std::string{table});
    tx.commit();
    return;
  } catch (const pqxx::unique_violation&) {
  }
  // ...which then goes through the staging table, skipping what is stored.
  pqxx::work tx(c);
  stream(tx, fmt::format("sf_staging_{}", table));
  const auto list = fmt::format("{}", fmt::join(columns, ", "));
  tx.exec(fmt::format("INSERT INTO {0} ({1}) SELECT {1} FROM sf_staging_{0} ON CONFLICT DO NOTHING", table,
                      list));
  tx.commit();
}

void PgStore::with_partitions(pqxx::connection& c, Partitions& parts, std::span<const std::int64_t> times,
                              const std::function<void()>& write) {
  parts.ensure(c, times);
  try {
    write();
  } catch (const pqxx::check_violation&) {
    // "no partition of relation ... found for row"
    parts.forget();
    parts.ensure(c, times);
    write();
  }
}

Status PgStore::append(std::span<const Sample> samples) {
  if (samples.empty()) {
    return {};
  }
  auto lookup = [&](SeriesId id) -> Result<bool> {
    auto found = find_series(id);
    return found ? Result<bool>{found->has_value()} : Result<bool>{found.error()};
  };
  SF_TRY(known_.check(samples, lookup));
  std::vector<std::int64_t> times;
  times.reserve(samples.size());
  for (const auto& s : samples) {
    times.push_back(to_micros(s.source_time));
  }
  const auto row = [](const Sample& s) {
    auto c = detail::to_columns(s.value);
    return std::make_tuple(s.series, to_micros(s.source_time), std::int64_t{s.seq}, to_micros(s.server_time),
                           std::int64_t{s.status}, c.vtype, c.v_int,
                           c.v_real ? std::optional{double_text(*c.v_real)} : std::nullopt,
                           std::move(c.v_text),
                           c.v_blob ? std::optional{bytea_text(*c.v_blob)} : std::nullopt);
  };
  return conn_.run(fmt::format("append {} samples", samples.size()), [&](pqxx::connection& c) {
    with_partitions(c, sample_parts_, times, [&] { copy_in(c, "samples", sample_columns(), samples, row); });
  });
}

Status PgStore::append_events(std::span<const Event> events) {
  if (events.empty()) {
    return {};
  }
  std::vector<std::int64_t> times;
  times.reserve(events.size());
  for (const auto& e : events) {
    times.push_back(to_micros(e.time));
  }
  const auto row = [](const Event& e) {
    return std::make_tuple(e.server, bytea_text(e.event_id), to_micros(e.time), to_micros(e.receive_time),
                           e.event_type, e.source_node, e.source_name, int{e.severity}, e.message, e.fields);
  };
  return conn_.run(fmt::format("append {} events", events.size()), [&](pqxx::connection& c) {
    with_partitions(c, event_parts_, times, [&] { copy_in(c, "events", event_columns(), events, row); });
  });
}

Result<std::vector<Sample>> PgStore::read_raw(SeriesId series, Timestamp from, Timestamp to,
                                              std::size_t limit) {
  auto rows = conn_.run("read samples", [&](pqxx::connection& c) {
    pqxx::nontransaction tx(c);
    return tx.exec_prepared("read_raw", series, to_micros(from), to_micros(to), clamp_limit(limit));
  });
  if (!rows) {
    return rows.error();
  }
  return samples_from(*rows, series);
}

Result<std::optional<Sample>> PgStore::latest(SeriesId series) {
  auto rows = conn_.run("latest sample", [&](pqxx::connection& c) {
    pqxx::nontransaction tx(c);
    return tx.exec_prepared("latest", series);
  });
  if (!rows) {
    return rows.error();
  }
  auto samples = samples_from(*rows, series);
  if (!samples) {
    return samples.error();
  }
  return samples->empty() ? std::optional<Sample>{} : std::optional<Sample>{std::move(samples->front())};
}

Result<std::vector<AggregateRow>> PgStore::aggregate(SeriesId series, Timestamp from, Timestamp to,
                                                     Micros interval, Aggregate which) {
  if (interval.count() <= 0) {
    return make_error(Errc::invalid_argument, "aggregate interval must be positive");
  }
  auto rows = conn_.run("aggregate", [&](pqxx::connection& c) {
    pqxx::nontransaction tx(c);
    return tx.exec_prepared("aggregate", series, to_micros(from), to_micros(to),
                            std::int64_t{interval.count()});
  });
  if (!rows) {
    return rows.error();
  }
  std::vector<AggregateRow> out;
  for (const auto& r : *rows) {
    AggregateRow row;
    row.start = from + as_int64(r[0]) * interval;
    if (has(which, Aggregate::count)) {
      row.count = static_cast<std::uint64_t>(as_int64(r[1]));
    }
    if (has(which, Aggregate::min)) {
      row.min = as_opt_double(r[2]);
    }
    if (has(which, Aggregate::max)) {
      row.max = as_opt_double(r[3]);
    }
    if (has(which, Aggregate::avg)) {
      row.avg = as_opt_double(r[4]);
    }
    out.push_back(row);
  }
  return out;
}

Result<std::vector<Event>> PgStore::read_events(const EventQuery& query) {
  return conn_.run("read events", [&](pqxx::connection& c) {
    pqxx::nontransaction tx(c);
    std::vector<Event> out;
    for (const auto& r : tx.exec_prepared("read_events", to_micros(query.from), to_micros(query.to),
                                          query.server, clamp_limit(query.limit))) {
      out.push_back(Event{r[0].c_str(), as_bytes(r[1]), from_micros(as_int64(r[2])),
                          from_micros(as_int64(r[3])), r[4].c_str(), r[5].c_str(), r[6].c_str(),
                          static_cast<std::uint16_t>(as_int64(r[7])), r[8].c_str(), r[9].c_str()});
    }
    return out;
  });
}

Result<RetentionResult> PgStore::apply_retention(Timestamp before) {
  return conn_.run("retention", [&](pqxx::connection& c) {
    RetentionResult result;
    const auto t = to_micros(before);
    result.partitions_dropped =
        drop_partitions_before(c, "samples", t) + drop_partitions_before(c, "events", t);
    sample_parts_.forget();
    event_parts_.forget();
    // What is left before `before` lies in the one partition that straddles it.
    pqxx::work tx(c);
    result.samples_deleted = tx.exec_params("DELETE FROM samples WHERE source_time < $1", t).affected_rows();
    result.events_deleted = tx.exec_params("DELETE FROM events WHERE time < $1", t).affected_rows();
    tx.commit();
    return result;
  });
}

}  // namespace

Result<std::unique_ptr<Store>> open_store(const detail::StoreUrl& url, const StoreOptions& options) {
  const auto redacted = detail::redact_url(url.target);
  SF_TRY(validate_conninfo(url.target, redacted));
  auto store = std::make_unique<PgStore>(url.target, redacted);
  SF_TRY(store->open(options));
  return std::unique_ptr<Store>{std::move(store)};
}

}  // namespace sf::historian::postgres
