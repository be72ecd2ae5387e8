// A thin RAII layer over the SQLite C API: a connection, prepared statements
// with sticky bind errors, and one mapping of SQLite result codes to Errc
// (see store.hpp: Errc::io = "try again later").
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

#include <sqlite3.h>

#include "sf/core/bytes.hpp"
#include "sf/core/result.hpp"

namespace sf::historian::sqlite {

// Busy/locked/I-O/full/cannot-open → io; corrupt/not-a-database → malformed;
// foreign key → not_found; other constraints → invalid_argument; else state.
Error to_error(int rc, std::string_view what, std::string_view detail);

class Statement {
 public:
  Statement() = default;
  Statement(sqlite3* db, sqlite3_stmt* stmt) : db_(db), stmt_(stmt) {}
  ~Statement();
  Statement(Statement&& other) noexcept;
  Statement& operator=(Statement&& other) noexcept;
  Statement(const Statement&) = delete;
  Statement& operator=(const Statement&) = delete;

  // Parameters count from 1, as in SQL (?1, ?2, ...).
  Statement& bind(int i, std::int64_t v);
  Statement& bind(int i, double v);
  Statement& bind(int i, std::string_view v);
  Statement& bind(int i, ByteSpan v);
  Statement& bind_null(int i);
  template <typename T>
  Statement& bind(int i, const std::optional<T>& v) {
    return v ? bind(i, *v) : bind_null(i);
  }

  // true: a row is ready; false: done. Errors include bind errors.
  Result<bool> step();
  // Runs to completion (a statement that returns no rows).
  Status run();
  // Steps through every row, calling on_row() (returning Status) for each.
  template <typename F>
  Status for_each_row(F&& on_row) {
    for (;;) {
      auto row = step();
      if (!row) {
        return row.error();
      }
      if (!*row) {
        return {};
      }
      SF_TRY(on_row());
    }
  }
  // Ready for new bindings and another run.
  void reset();

  [[nodiscard]] bool is_null(int col) const;
  [[nodiscard]] std::int64_t int64(int col) const;
  [[nodiscard]] double real(int col) const;
  [[nodiscard]] std::string text(int col) const;
  [[nodiscard]] Bytes blob(int col) const;
  [[nodiscard]] std::optional<std::int64_t> opt_int64(int col) const;
  [[nodiscard]] std::optional<double> opt_real(int col) const;
  [[nodiscard]] std::optional<std::string> opt_text(int col) const;
  [[nodiscard]] std::optional<Bytes> opt_blob(int col) const;

 private:
  void check_bind(int rc);

  sqlite3* db_ = nullptr;
  sqlite3_stmt* stmt_ = nullptr;
  int bind_rc_ = SQLITE_OK;
};

class Db {
 public:
  Db() = default;
  ~Db();
  Db(Db&& other) noexcept : db_(other.db_) { other.db_ = nullptr; }
  Db& operator=(Db&& other) noexcept;
  Db(const Db&) = delete;
  Db& operator=(const Db&) = delete;

  // Opens (creating) the file; ":memory:" for a private in-memory database.
  static Result<Db> open(const std::string& path);

  // Runs one or more statements separated by ';' (no results).
  Status exec(std::string_view sql);
  Result<Statement> prepare(std::string_view sql);
  // The first column of the first row of a query as text (PRAGMA answers).
  Result<std::string> query_text(std::string_view sql);
  [[nodiscard]] std::int64_t changes() const;
  [[nodiscard]] sqlite3* handle() const { return db_; }

 private:
  explicit Db(sqlite3* db) : db_(db) {}
  sqlite3* db_ = nullptr;
};

// BEGIN IMMEDIATE ... COMMIT, rolled back unless committed. IMMEDIATE takes
// the write lock up front, so a busy database fails at BEGIN (after the busy
// timeout) rather than half-way through a batch.
class Transaction {
 public:
  explicit Transaction(Db& db) : db_(db) {}
  ~Transaction();
  Transaction(const Transaction&) = delete;
  Transaction& operator=(const Transaction&) = delete;

  Status begin();
  Status commit();

 private:
  Db& db_;
  bool open_ = false;
};

}  // namespace sf::historian::sqlite
