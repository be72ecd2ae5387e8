// One PostgreSQL connection that comes back by itself: every operation runs
// through run(), which (re)connects when needed, turns libpqxx exceptions into
// Errors (nothing throws out of the historian) and forgets a connection that
// an error may have broken, so the next call reconnects.
#pragma once

#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <type_traits>

#include <pqxx/pqxx>

#include "sf/core/bytes.hpp"
#include "sf/core/result.hpp"

namespace sf::historian::postgres {

// broken connection, commit outcome unknown, SQLSTATE classes 08 (connection),
// 53 (resources), 57P (shutdown), 40 (rollback) → io; 23503 (foreign key) →
// not_found; other 23 (integrity) and 22 (data) → invalid_argument; else state.
Error to_error(const std::exception& e, std::string_view what);

// Checks the URL's syntax as libpq parses it, before any connection attempt,
// so a typo is reported as a bad URL (Errc::invalid_argument), not as an
// unreachable database.
Status validate_conninfo(const std::string& conninfo, std::string_view redacted);

class Connection {
 public:
  using Setup = std::function<void(pqxx::connection&)>;

  // `setup` runs on every new connection (session settings, prepared
  // statements, temporary tables) and may throw.
  Connection(std::string conninfo, std::string redacted, Setup setup)
      : conninfo_(std::move(conninfo)), redacted_(std::move(redacted)), setup_(std::move(setup)) {}

  // Runs f(connection); exceptions become errors prefixed with `what`.
  template <typename F>
  auto run(std::string_view what, F&& f) -> Result<std::invoke_result_t<F, pqxx::connection&>> {
    using R = std::invoke_result_t<F, pqxx::connection&>;
    auto conn = connect();
    if (!conn) {
      return conn.error();  // says itself what it tried
    }
    try {
      if constexpr (std::is_void_v<R>) {
        f(**conn);
        return {};
      } else {
        return f(**conn);
      }
    } catch (const std::exception& e) {
      return failed(e, what);
    }
  }

  // Forgets the connection (tests of reconnection; errors do this themselves).
  void drop() { conn_.reset(); }
  [[nodiscard]] const std::string& redacted_url() const { return redacted_; }

 private:
  Result<pqxx::connection*> connect();
  Error failed(const std::exception& e, std::string_view what);

  std::string conninfo_;
  std::string redacted_;
  Setup setup_;
  std::unique_ptr<pqxx::connection> conn_;
};

// Field helpers: libpqxx hands out text; these parse it exactly.
std::int64_t as_int64(const pqxx::field& f);
std::optional<std::int64_t> as_opt_int64(const pqxx::field& f);
std::optional<double> as_opt_double(const pqxx::field& f);
std::optional<std::string> as_opt_text(const pqxx::field& f);
// bytea in hex output format ("\x0102ff").
Bytes as_bytes(const pqxx::field& f);
std::optional<Bytes> as_opt_bytes(const pqxx::field& f);

// Text a COPY or a parameter carries: doubles round-trip exactly (shortest
// form; NaN and infinities spelled as PostgreSQL reads them), bytea as hex.
std::string double_text(double v);
std::string bytea_text(ByteSpan b);

}  // namespace sf::historian::postgres
