#include "postgres/pg_connection.hpp"

#include <charconv>
#include <cmath>

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <libpq-fe.h>

#include "sf/core/log.hpp"

namespace sf::historian::postgres {

namespace {

Errc classify_sqlstate(std::string_view state) {
  if (state.starts_with("08") || state.starts_with("53") || state.starts_with("57P") ||
      state.starts_with("40")) {
    return Errc::io;
  }
  if (state == "23503") {
    return Errc::not_found;
  }
  if (state.starts_with("23") || state.starts_with("22")) {
    return Errc::invalid_argument;
  }
  return Errc::state;
}

std::string first_line(std::string_view text) {
  while (!text.empty() && (text.back() == '\n' || text.back() == ' ')) {
    text.remove_suffix(1);
  }
  return std::string{text.substr(0, text.find('\n'))};
}

}  // namespace

Error to_error(const std::exception& e, std::string_view what) {
  const std::string message = first_line(e.what());
  if (dynamic_cast<const pqxx::in_doubt_error*>(&e) != nullptr) {
    return make_error(
        Errc::io,
        fmt::format("postgresql {}: connection lost during commit, outcome unknown: {}", what, message));
  }
  if (dynamic_cast<const pqxx::broken_connection*>(&e) != nullptr) {
    return make_error(Errc::io, fmt::format("postgresql {}: database unreachable: {}", what, message));
  }
  if (const auto* sql = dynamic_cast<const pqxx::sql_error*>(&e); sql != nullptr) {
    return make_error(classify_sqlstate(sql->sqlstate()),
                      fmt::format("postgresql {}: {} (SQLSTATE {})", what, message, sql->sqlstate()));
  }
  return make_error(Errc::state, fmt::format("postgresql {}: {}", what, message));
}

Status validate_conninfo(const std::string& conninfo, std::string_view redacted) {
  char* message = nullptr;
  PQconninfoOption* options = PQconninfoParse(conninfo.c_str(), &message);
  if (options == nullptr) {
    auto error = make_error(Errc::invalid_argument,
                            fmt::format("bad store URL '{}': {}", redacted,
                                        first_line(message != nullptr ? message : "cannot be parsed")));
    PQfreemem(message);
    return error;
  }
  PQconninfoFree(options);
  return {};
}

Result<pqxx::connection*> Connection::connect() {
  if (conn_ && conn_->is_open()) {
    return conn_.get();
  }
  conn_.reset();
  try {
    auto conn = std::make_unique<pqxx::connection>(conninfo_);
    setup_(*conn);
    conn_ = std::move(conn);
    return conn_.get();
  } catch (const std::exception& e) {
    auto error = to_error(e, fmt::format("connect to {}", redacted_));
    // A server that refuses us outright (bad password, no such database) is
    // as unreachable as one that is down: the caller may retry either way.
    if (dynamic_cast<const pqxx::sql_error*>(&e) == nullptr) {
      error.code = Errc::io;
    }
    return error;
  }
}

Error Connection::failed(const std::exception& e, std::string_view what) {
  auto error = to_error(e, what);
  if (error.code == Errc::io) {
    conn_.reset();
  }
  return error;
}

std::int64_t as_int64(const pqxx::field& f) {
  std::int64_t v = 0;
  const char* s = f.c_str();
  std::from_chars(s, s + f.size(), v);
  return v;
}

std::optional<std::int64_t> as_opt_int64(const pqxx::field& f) {
  return f.is_null() ? std::nullopt : std::optional{as_int64(f)};
}

std::optional<double> as_opt_double(const pqxx::field& f) {
  if (f.is_null()) {
    return std::nullopt;
  }
  const std::string_view s{f.c_str(), f.size()};
  if (s == "NaN") {
    return std::nan("");
  }
  if (s == "Infinity" || s == "-Infinity") {
    return s.front() == '-' ? -HUGE_VAL : HUGE_VAL;
  }
  double v = 0;
  std::from_chars(s.data(), s.data() + s.size(), v);
  return v;
}

std::optional<std::string> as_opt_text(const pqxx::field& f) {
  return f.is_null() ? std::nullopt : std::optional{std::string{f.c_str(), f.size()}};
}

Bytes as_bytes(const pqxx::field& f) {
  // bytea_output = hex (the default since PostgreSQL 9.0): "\x0102ff".
  const std::string_view s{f.c_str(), f.size()};
  return s.starts_with("\\x") ? from_hex(s.substr(2)).value_or({}) : Bytes{};
}

std::optional<Bytes> as_opt_bytes(const pqxx::field& f) {
  return f.is_null() ? std::nullopt : std::optional{as_bytes(f)};
}

std::string double_text(double v) {
  if (std::isnan(v)) {
    return "NaN";
  }
  if (std::isinf(v)) {
    return v < 0 ? "-Infinity" : "Infinity";
  }
  return fmt::format("{}", v);
}

std::string bytea_text(ByteSpan b) {
  return fmt::format("\\x{:02x}", fmt::join(b, ""));
}

}  // namespace sf::historian::postgres
