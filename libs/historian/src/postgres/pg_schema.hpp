// The PostgreSQL schema, its migrations and its time partitions.
//
// samples and events are range-partitioned on their time column (bigint µs),
// one partition per `partition width` (a day by default), created on demand
// and recorded in sf_partitions so retention can drop whole partitions
// instead of deleting rows one by one.
#pragma once

#include <cstdint>
#include <optional>
#include <set>
#include <span>
#include <string>
#include <string_view>

#include <pqxx/pqxx>

#include "migrations.hpp"
#include "sf/historian/types.hpp"

namespace sf::historian::postgres {

// These throw on failure (run them through Connection::run).
std::span<const detail::Migration> migrations();
// Creates schema_migrations when missing.
void bootstrap_migrations(pqxx::connection& conn);
// One migration in one transaction, skipped when another program applied it.
void apply_migration(pqxx::connection& conn, const detail::Migration& m);
int schema_version(pqxx::connection& conn);
// The database's partition width: stored on first open, later opens use it
// whatever they ask for (partitions of two widths would overlap).
Micros partition_width(pqxx::connection& conn, Micros wanted);

// The partitions a table needs for a set of times, created when missing.
class Partitions {
 public:
  Partitions(std::string table, Micros width) : table_(std::move(table)), width_(width) {}

  // Creates (in its own transaction) the partitions for `times` not known yet.
  void ensure(pqxx::connection& conn, std::span<const std::int64_t> times);
  // After another process dropped partitions (retention): forget what we know.
  void forget() { known_.clear(); }

  [[nodiscard]] std::int64_t start_of(std::int64_t t) const;
  [[nodiscard]] std::string name_of(std::int64_t start) const;

 private:
  std::string table_;
  Micros width_;
  std::set<std::int64_t> known_;
};

// Drops every partition of `table` that ends at or before `before`.
std::uint64_t drop_partitions_before(pqxx::connection& conn, std::string_view table, std::int64_t before);

}  // namespace sf::historian::postgres
