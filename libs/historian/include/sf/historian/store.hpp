// Store: the historian's one interface. Two real back ends implement it —
// SQLite (embedded, the default) and PostgreSQL (libpqxx) — chosen by URL,
// and BufferedStore (buffered_store.hpp) wraps either with store-and-forward.
//
// Errors: Errc::io means "the database is unreachable or failed; the same call
// may succeed later" (connection refused or lost, file locked, disk error);
// every other code means the request itself is wrong and retrying will not
// help. BufferedStore relies on this split.
//
// A Store object is not thread-safe; BufferedStore serialises its callers.
#pragma once

#include <cstddef>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "sf/core/result.hpp"
#include "sf/historian/types.hpp"

namespace sf::historian {

class Store {
 public:
  virtual ~Store() = default;

  // Adds the series or updates its description; idempotent by (server, node_id).
  virtual Result<SeriesId> register_series(const SeriesInfo& info) = 0;
  virtual Result<std::vector<Series>> list_series() = 0;

  // Writes a batch in one transaction: all samples or none. Samples whose key
  // (series, source_time, seq) is already stored are skipped, so a batch may
  // be re-sent after an error without creating duplicates. Every sample's
  // series must be registered (Errc::not_found otherwise).
  virtual Status append(std::span<const Sample> samples) = 0;
  // Same for events, keyed by (server, event_id, time).
  virtual Status append_events(std::span<const Event> events) = 0;

  // Samples with from <= source_time < to, oldest first (then by seq), at most `limit`.
  virtual Result<std::vector<Sample>> read_raw(SeriesId series, Timestamp from, Timestamp to,
                                               std::size_t limit) = 0;
  // The sample with the newest source time (highest seq among equals).
  virtual Result<std::optional<Sample>> latest(SeriesId series) = 0;
  // One row per interval [from + k*interval, from + (k+1)*interval) that holds
  // at least one non-Bad sample, oldest first. Fields not in `which` are empty.
  virtual Result<std::vector<AggregateRow>> aggregate(SeriesId series, Timestamp from, Timestamp to,
                                                      Micros interval, Aggregate which) = 0;
  virtual Result<std::vector<Event>> read_events(const EventQuery& query) = 0;

  // Deletes samples and events older than `before` (source time / event time).
  virtual Result<RetentionResult> apply_retention(Timestamp before) = 0;
  // The version of the schema in the database (migrations applied on open).
  virtual Result<int> schema_version() = 0;
  // "sqlite" or "postgresql".
  [[nodiscard]] virtual std::string_view backend() const = 0;
};

struct StoreOptions {
  // PostgreSQL: width of a time partition of the samples and events tables.
  Micros partition_width = std::chrono::hours{24};
  // Apply migrations up to this version only (tests of the migration path).
  std::optional<int> schema_target;
};

// Opens (creating when needed) the store a URL names and brings its schema
// up to date:
//   sqlite:PATH[?busy_timeout_ms=N&synchronous=normal|full]   (sqlite::memory: for tests)
//   postgresql://user@host:port/db[?libpq parameters]   (also postgres://)
// A malformed URL gives Errc::invalid_argument, an unreachable database Errc::io.
Result<std::unique_ptr<Store>> open_store(std::string_view url, const StoreOptions& options = {});

// The newest schema version this build knows (both back ends).
[[nodiscard]] int latest_schema_version();

}  // namespace sf::historian
