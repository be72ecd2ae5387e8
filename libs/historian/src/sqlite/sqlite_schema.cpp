#include "sqlite/sqlite_schema.hpp"

#include <array>

#include "migrations.hpp"

namespace sf::historian::sqlite {

namespace {

using detail::Migration;

// Samples are a WITHOUT ROWID table clustered on (series_id, source_time,
// seq): the primary key is the index for per-series time ranges and the key
// that makes re-delivered samples no-ops. Times are int64 microseconds (UTC).
constexpr std::string_view kV1 = R"sql(
CREATE TABLE series (
  id          INTEGER PRIMARY KEY,
  server      TEXT    NOT NULL,
  node_id     TEXT    NOT NULL,
  browse_path TEXT    NOT NULL,
  data_type   INTEGER NOT NULL,
  unit        TEXT    NOT NULL,
  UNIQUE (server, node_id));
CREATE TABLE samples (
  series_id   INTEGER NOT NULL REFERENCES series (id),
  source_time INTEGER NOT NULL,
  seq         INTEGER NOT NULL,
  server_time INTEGER NOT NULL,
  status      INTEGER NOT NULL,
  vtype       INTEGER NOT NULL,
  v_int       INTEGER,
  v_real      REAL,
  v_text      TEXT,
  v_blob      BLOB,
  PRIMARY KEY (series_id, source_time, seq)) WITHOUT ROWID;
CREATE TABLE events (
  server       TEXT    NOT NULL,
  event_id     BLOB    NOT NULL,
  time         INTEGER NOT NULL,
  receive_time INTEGER NOT NULL,
  event_type   TEXT    NOT NULL,
  source_node  TEXT    NOT NULL,
  source_name  TEXT    NOT NULL,
  severity     INTEGER NOT NULL,
  message      TEXT    NOT NULL,
  fields       TEXT    NOT NULL,
  PRIMARY KEY (server, event_id, time)) WITHOUT ROWID;
)sql";

// Time-only indexes: retention deletes by time across all series, and event
// queries select by time first.
constexpr std::string_view kV2 = R"sql(
CREATE INDEX samples_by_time ON samples (source_time);
CREATE INDEX events_by_time ON events (time);
)sql";

constexpr std::array<Migration, 2> kMigrations{{
    {1, "series, samples and events tables", kV1},
    {2, "time indexes for retention and event queries", kV2},
}};
static_assert(kMigrations.back().version == detail::kSchemaVersion);

Result<bool> applied(Db& db, int version) {
  auto stmt = db.prepare("SELECT 1 FROM schema_migrations WHERE version = ?1");
  if (!stmt) {
    return stmt.error();
  }
  stmt->bind(1, std::int64_t{version});
  return stmt->step();
}

Status apply(Db& db, const Migration& m) {
  Transaction tx(db);
  SF_TRY(tx.begin());
  auto done = applied(db, m.version);
  if (!done) {
    return done.error();
  }
  if (*done) {
    return {};
  }
  SF_TRY(db.exec(m.sql));
  auto record = db.prepare(
      "INSERT INTO schema_migrations (version, description, applied_at) "
      "VALUES (?1, ?2, CAST(strftime('%s', 'now') AS INTEGER) * 1000000)");
  if (!record) {
    return record.error();
  }
  record->bind(1, std::int64_t{m.version}).bind(2, m.description);
  SF_TRY(record->run());
  return tx.commit();
}

}  // namespace

Result<int> schema_version(Db& db) {
  auto stmt = db.prepare("SELECT coalesce(max(version), 0) FROM schema_migrations");
  if (!stmt) {
    return stmt.error();
  }
  auto row = stmt->step();
  if (!row) {
    return row.error();
  }
  return static_cast<int>(stmt->int64(0));
}

Status migrate(Db& db, std::optional<int> up_to) {
  SF_TRY(
      db.exec("CREATE TABLE IF NOT EXISTS schema_migrations ("
              "version INTEGER PRIMARY KEY, description TEXT NOT NULL, applied_at INTEGER NOT NULL)"));
  const detail::MigrationTarget target{"sqlite", [&] { return schema_version(db); },
                                       [&](const Migration& m) { return apply(db, m); }};
  return detail::run_migrations(kMigrations, target, up_to);
}

}  // namespace sf::historian::sqlite
