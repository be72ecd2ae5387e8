#include "postgres/pg_schema.hpp"

#include <array>
#include <vector>

#include <fmt/format.h>

#include "migrations.hpp"
#include "postgres/pg_connection.hpp"
#include "sf/core/log.hpp"

namespace sf::historian::postgres {

namespace {

using detail::Migration;

// Any fixed number: the advisory lock that serialises migrations of
// programs opening the same database at once.
constexpr std::int64_t kMigrationLock = 0x5346'4869'7374'0001;

constexpr std::string_view kV1 = R"sql(
CREATE TABLE series (
  id          bigint   PRIMARY KEY,
  server      text     NOT NULL,
  node_id     text     NOT NULL,
  browse_path text     NOT NULL,
  data_type   smallint NOT NULL,
  unit        text     NOT NULL,
  UNIQUE (server, node_id));
CREATE TABLE samples (
  series_id   bigint   NOT NULL REFERENCES series (id),
  source_time bigint   NOT NULL,
  seq         bigint   NOT NULL,
  server_time bigint   NOT NULL,
  status      bigint   NOT NULL,
  vtype       smallint NOT NULL,
  v_int       bigint,
  v_real      double precision,
  v_text      text,
  v_blob      bytea,
  PRIMARY KEY (series_id, source_time, seq)) PARTITION BY RANGE (source_time);
CREATE TABLE events (
  server       text    NOT NULL,
  event_id     bytea   NOT NULL,
  time         bigint  NOT NULL,
  receive_time bigint  NOT NULL,
  event_type   text    NOT NULL,
  source_node  text    NOT NULL,
  source_name  text    NOT NULL,
  severity     integer NOT NULL,
  message      text    NOT NULL,
  fields       text    NOT NULL,
  PRIMARY KEY (server, event_id, time)) PARTITION BY RANGE (time);
CREATE TABLE sf_partitions (
  name   text   PRIMARY KEY,
  parent text   NOT NULL,
  lo     bigint NOT NULL,
  hi     bigint NOT NULL);
CREATE TABLE sf_settings (key text PRIMARY KEY, value text NOT NULL);
)sql";

// Indexes on a partitioned table reach every partition, present and future.
constexpr std::string_view kV2 = R"sql(
CREATE INDEX samples_by_time ON samples (source_time);
CREATE INDEX events_by_time ON events (time);
)sql";

constexpr std::array<Migration, 2> kMigrations{{
    {1, "series, partitioned samples and events, partition registry, settings", kV1},
    {2, "time indexes for retention and event queries", kV2},
}};
static_assert(kMigrations.back().version == detail::kSchemaVersion);

void lock(pqxx::work& tx) {
  tx.exec_params("SELECT pg_advisory_xact_lock($1)", kMigrationLock);
}

// floor(a / b) for b > 0, also for negative a.
std::int64_t floor_div(std::int64_t a, std::int64_t b) {
  const std::int64_t q = a / b;
  return (a % b != 0 && a < 0) ? q - 1 : q;
}

}  // namespace

std::span<const Migration> migrations() {
  return kMigrations;
}

void apply_migration(pqxx::connection& conn, const Migration& m) {
  pqxx::work tx(conn);
  lock(tx);
  if (!tx.exec_params("SELECT 1 FROM schema_migrations WHERE version = $1", m.version).empty()) {
    return;  // another program was first
  }
  tx.exec(std::string{m.sql});
  tx.exec_params(
      "INSERT INTO schema_migrations (version, description, applied_at) "
      "VALUES ($1, $2, (extract(epoch FROM now()) * 1000000)::bigint)",
      m.version, std::string{m.description});
  tx.commit();
}

int schema_version(pqxx::connection& conn) {
  pqxx::nontransaction tx(conn);
  return static_cast<int>(as_int64(tx.exec("SELECT coalesce(max(version), 0) FROM schema_migrations")[0][0]));
}

void bootstrap_migrations(pqxx::connection& conn) {
  pqxx::work tx(conn);
  lock(tx);
  tx.exec(
      "CREATE TABLE IF NOT EXISTS schema_migrations ("
      "version integer PRIMARY KEY, description text NOT NULL, applied_at bigint NOT NULL)");
  tx.commit();
}

Micros partition_width(pqxx::connection& conn, Micros wanted) {
  pqxx::work tx(conn);
  tx.exec_params(
      "INSERT INTO sf_settings (key, value) VALUES ('partition_width_us', $1) ON CONFLICT DO NOTHING",
      std::to_string(wanted.count()));
  const auto stored =
      as_int64(tx.exec("SELECT value FROM sf_settings WHERE key = 'partition_width_us'")[0][0]);
  tx.commit();
  if (stored != wanted.count()) {
    log::get("historian")
        ->info("postgresql: database partitions by {} µs (asked for {} µs)", stored, wanted.count());
  }
  return Micros{stored};
}

std::int64_t Partitions::start_of(std::int64_t t) const {
  return floor_div(t, width_.count()) * width_.count();
}

std::string Partitions::name_of(std::int64_t start) const {
  // samples_p20261121 for day-aligned partitions, samples_p20261121_0600 for
  // others; the raw microseconds only for times outside years 1000..9999.
  const auto t = from_micros(start);
  const auto day = std::chrono::floor<std::chrono::days>(t);
  const std::chrono::year_month_day ymd{day};
  const int year = static_cast<int>(ymd.year());
  if (year < 1000 || year > 9999) {
    return fmt::format("{}_pu{}", table_,
                       start < 0 ? "m" + std::to_string(-(start + 1)) : std::to_string(start));
  }
  auto name = fmt::format("{}_p{:04}{:02}{:02}", table_, year, static_cast<unsigned>(ymd.month()),
                          static_cast<unsigned>(ymd.day()));
  if (const auto rest = std::chrono::duration_cast<std::chrono::seconds>(t - day).count(); rest != 0) {
    name += fmt::format("_{:02}{:02}{:02}", rest / 3600, rest / 60 % 60, rest % 60);
  }
  return name;
}

void Partitions::ensure(pqxx::connection& conn, std::span<const std::int64_t> times) {
  std::vector<std::int64_t> missing;
  for (const auto t : times) {
    const auto start = start_of(t);
    if (!known_.contains(start) && (missing.empty() || missing.back() != start)) {
      missing.push_back(start);
    }
  }
  if (missing.empty()) {
    return;
  }
  pqxx::work tx(conn);
  lock(tx);  // two writers creating the same partition would collide in the catalog
  for (const auto start : missing) {
    const auto name = name_of(start);
    const auto end = start + width_.count();
    tx.exec(fmt::format("CREATE TABLE IF NOT EXISTS {} PARTITION OF {} FOR VALUES FROM ({}) TO ({})",
                        tx.quote_name(name), table_, start, end));
    tx.exec_params(
        "INSERT INTO sf_partitions (name, parent, lo, hi) VALUES ($1, $2, $3, $4) ON CONFLICT DO NOTHING",
        name, table_, start, end);
  }
  tx.commit();
  known_.insert(missing.begin(), missing.end());
}

std::uint64_t drop_partitions_before(pqxx::connection& conn, std::string_view table, std::int64_t before) {
  pqxx::work tx(conn);
  lock(tx);
  const auto old = tx.exec_params("SELECT name FROM sf_partitions WHERE parent = $1 AND hi <= $2 ORDER BY lo",
                                  std::string{table}, before);
  for (const auto& row : old) {
    const std::string name = row[0].c_str();
    tx.exec(fmt::format("DROP TABLE IF EXISTS {}", tx.quote_name(name)));
    tx.exec_params("DELETE FROM sf_partitions WHERE name = $1", name);
  }
  tx.commit();
  return old.size();
}

}  // namespace sf::historian::postgres
