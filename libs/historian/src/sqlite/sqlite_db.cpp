#include "sqlite/sqlite_db.hpp"

#include <utility>

#include <fmt/format.h>

namespace sf::historian::sqlite {

Error to_error(int rc, std::string_view what, std::string_view detail) {
  Errc code = Errc::state;
  switch (rc & 0xff) {
    case SQLITE_BUSY:
    case SQLITE_LOCKED:
    case SQLITE_IOERR:
    case SQLITE_FULL:
    case SQLITE_CANTOPEN:
    case SQLITE_PROTOCOL:
    case SQLITE_READONLY:
    case SQLITE_NOMEM:
      code = Errc::io;
      break;
    case SQLITE_CORRUPT:
    case SQLITE_NOTADB:
      code = Errc::malformed;
      break;
    case SQLITE_CONSTRAINT:
      // A sample of a series the database does not know: as PostgreSQL's 23503.
      code = rc == SQLITE_CONSTRAINT_FOREIGNKEY ? Errc::not_found : Errc::invalid_argument;
      break;
    default:
      break;
  }
  const std::string_view general = sqlite3_errstr(rc);
  return make_error(code, detail == general ? fmt::format("sqlite {}: {}", what, detail)
                                            : fmt::format("sqlite {}: {} ({})", what, detail, general));
}

namespace {

Error db_error(sqlite3* db, int rc, std::string_view what) {
  return to_error(rc, what, db != nullptr ? sqlite3_errmsg(db) : sqlite3_errstr(rc));
}

}  // namespace

// --- Statement -----------------------------------------------------------------

Statement::~Statement() {
  sqlite3_finalize(stmt_);
}

Statement::Statement(Statement&& other) noexcept
    : db_(std::exchange(other.db_, nullptr)),
      stmt_(std::exchange(other.stmt_, nullptr)),
      bind_rc_(other.bind_rc_) {}

Statement& Statement::operator=(Statement&& other) noexcept {
  if (this != &other) {
    sqlite3_finalize(stmt_);
    db_ = std::exchange(other.db_, nullptr);
    stmt_ = std::exchange(other.stmt_, nullptr);
    bind_rc_ = other.bind_rc_;
  }
  return *this;
}

void Statement::check_bind(int rc) {
  if (rc != SQLITE_OK && bind_rc_ == SQLITE_OK) {
    bind_rc_ = rc;
  }
}

Statement& Statement::bind(int i, std::int64_t v) {
  check_bind(sqlite3_bind_int64(stmt_, i, v));
  return *this;
}

Statement& Statement::bind(int i, double v) {
  check_bind(sqlite3_bind_double(stmt_, i, v));
  return *this;
}

Statement& Statement::bind(int i, std::string_view v) {
  check_bind(sqlite3_bind_text64(stmt_, i, v.data(), v.size(), SQLITE_TRANSIENT, SQLITE_UTF8));
  return *this;
}

Statement& Statement::bind(int i, ByteSpan v) {
  // A zero-length blob with a null pointer would bind NULL.
  static constexpr std::uint8_t kEmpty = 0;
  check_bind(sqlite3_bind_blob64(stmt_, i, v.empty() ? &kEmpty : v.data(), v.size(), SQLITE_TRANSIENT));
  return *this;
}

Statement& Statement::bind_null(int i) {
  check_bind(sqlite3_bind_null(stmt_, i));
  return *this;
}

Result<bool> Statement::step() {
  if (bind_rc_ != SQLITE_OK) {
    return db_error(db_, bind_rc_, "bind");
  }
  const int rc = sqlite3_step(stmt_);
  if (rc == SQLITE_ROW) {
    return true;
  }
  if (rc == SQLITE_DONE) {
    return false;
  }
  return db_error(db_, rc, "step");
}

Status Statement::run() {
  return for_each_row([] { return Status{}; });
}

void Statement::reset() {
  sqlite3_reset(stmt_);
  sqlite3_clear_bindings(stmt_);
  bind_rc_ = SQLITE_OK;
}

bool Statement::is_null(int col) const {
  return sqlite3_column_type(stmt_, col) == SQLITE_NULL;
}

std::int64_t Statement::int64(int col) const {
  return sqlite3_column_int64(stmt_, col);
}

double Statement::real(int col) const {
  return sqlite3_column_double(stmt_, col);
}

std::string Statement::text(int col) const {
  const auto* p = sqlite3_column_text(stmt_, col);
  const auto n = static_cast<std::size_t>(sqlite3_column_bytes(stmt_, col));
  return p == nullptr ? std::string{} : std::string{reinterpret_cast<const char*>(p), n};
}

Bytes Statement::blob(int col) const {
  const auto* p = static_cast<const std::uint8_t*>(sqlite3_column_blob(stmt_, col));
  const auto n = static_cast<std::size_t>(sqlite3_column_bytes(stmt_, col));
  return p == nullptr ? Bytes{} : Bytes{p, p + n};
}

std::optional<std::int64_t> Statement::opt_int64(int col) const {
  return is_null(col) ? std::nullopt : std::optional{int64(col)};
}

std::optional<double> Statement::opt_real(int col) const {
  return is_null(col) ? std::nullopt : std::optional{real(col)};
}

std::optional<std::string> Statement::opt_text(int col) const {
  return is_null(col) ? std::nullopt : std::optional{text(col)};
}

std::optional<Bytes> Statement::opt_blob(int col) const {
  return is_null(col) ? std::nullopt : std::optional{blob(col)};
}

// --- Db ------------------------------------------------------------------------

Db::~Db() {
  sqlite3_close_v2(db_);
}

Db& Db::operator=(Db&& other) noexcept {
  if (this != &other) {
    sqlite3_close_v2(db_);
    db_ = std::exchange(other.db_, nullptr);
  }
  return *this;
}

Result<Db> Db::open(const std::string& path) {
  sqlite3* db = nullptr;
  const int rc = sqlite3_open_v2(path.c_str(), &db, SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE, nullptr);
  if (rc != SQLITE_OK) {
    auto error = db_error(db, rc, fmt::format("open {}", path));
    sqlite3_close_v2(db);
    return error;
  }
  sqlite3_extended_result_codes(db, 1);
  return Db{db};
}

Status Db::exec(std::string_view sql) {
  const std::string text{sql};
  char* message = nullptr;
  const int rc = sqlite3_exec(db_, text.c_str(), nullptr, nullptr, &message);
  if (rc != SQLITE_OK) {
    auto error = to_error(rc, "exec", message != nullptr ? message : sqlite3_errstr(rc));
    sqlite3_free(message);
    return error;
  }
  return {};
}

Result<Statement> Db::prepare(std::string_view sql) {
  sqlite3_stmt* stmt = nullptr;
  const int rc = sqlite3_prepare_v3(db_, sql.data(), static_cast<int>(sql.size()), SQLITE_PREPARE_PERSISTENT,
                                    &stmt, nullptr);
  if (rc != SQLITE_OK) {
    return db_error(db_, rc, fmt::format("prepare '{}'", sql.substr(0, 60)));
  }
  return Statement{db_, stmt};
}

Result<std::string> Db::query_text(std::string_view sql) {
  auto stmt = prepare(sql);
  if (!stmt) {
    return stmt.error();
  }
  auto row = stmt->step();
  if (!row) {
    return row.error();
  }
  return *row ? stmt->text(0) : std::string{};
}

std::int64_t Db::changes() const {
  return sqlite3_changes64(db_);
}

// --- Transaction ---------------------------------------------------------------

Transaction::~Transaction() {
  if (open_) {
    (void)db_.exec("ROLLBACK");
  }
}

Status Transaction::begin() {
  SF_TRY(db_.exec("BEGIN IMMEDIATE"));
  open_ = true;
  return {};
}

Status Transaction::commit() {
  SF_TRY(db_.exec("COMMIT"));
  open_ = false;
  return {};
}

}  // namespace sf::historian::sqlite
