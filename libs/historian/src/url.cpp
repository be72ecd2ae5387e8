#include "url.hpp"

#include <fmt/format.h>

namespace sf::historian::detail {

namespace {

constexpr std::string_view kSqlite = "sqlite:";
constexpr std::string_view kUsage =
    "expected sqlite:PATH or postgresql://[user[:password]@]host[:port]/database";

Error bad_url(std::string_view url, std::string_view why) {
  return make_error(Errc::invalid_argument,
                    fmt::format("bad store URL '{}': {} ({})", redact_url(url), why, kUsage));
}

Result<std::map<std::string, std::string>> parse_params(std::string_view url, std::string_view query) {
  std::map<std::string, std::string> params;
  while (!query.empty()) {
    const auto amp = query.find('&');
    const auto pair = query.substr(0, amp);
    const auto eq = pair.find('=');
    if (eq == std::string_view::npos || eq == 0) {
      return bad_url(url, fmt::format("parameter '{}' is not key=value", pair));
    }
    params.emplace(std::string{pair.substr(0, eq)}, std::string{pair.substr(eq + 1)});
    query = amp == std::string_view::npos ? std::string_view{} : query.substr(amp + 1);
  }
  return params;
}

Result<StoreUrl> parse_sqlite(std::string_view url) {
  std::string_view rest = url.substr(kSqlite.size());
  std::string_view query;
  if (const auto q = rest.find('?'); q != std::string_view::npos) {
    query = rest.substr(q + 1);
    rest = rest.substr(0, q);
  }
  // sqlite:///abs/path (URL style) is the same file as sqlite:/abs/path.
  if (rest.starts_with("///")) {
    rest.remove_prefix(2);
  }
  if (rest.empty()) {
    return bad_url(url, "no file path after 'sqlite:'");
  }
  auto params = parse_params(url, query);
  if (!params) {
    return params.error();
  }
  for (const auto& [key, value] : *params) {
    if (key != "busy_timeout_ms" && key != "synchronous") {
      return bad_url(url, fmt::format("unknown parameter '{}' (busy_timeout_ms, synchronous)", key));
    }
  }
  StoreUrl out;
  out.backend = Backend::sqlite;
  out.target = rest == ":memory:" ? ":memory:" : std::string{rest};
  out.params = std::move(*params);
  return out;
}

// libpq waits for the OS's TCP timeout (minutes) on a host that does not
// answer; a historian should notice within seconds and buffer instead.
std::string with_pg_defaults(std::string_view url) {
  std::string out{url};
  const auto add = [&](std::string_view key, std::string_view value) {
    if (out.find(fmt::format("{}=", key)) != std::string::npos) {
      return;
    }
    out += out.find('?') == std::string::npos ? '?' : '&';
    out += fmt::format("{}={}", key, value);
  };
  add("connect_timeout", "5");
  add("tcp_user_timeout", "30000");
  return out;
}

}  // namespace

Result<StoreUrl> parse_store_url(std::string_view url) {
  if (url.empty()) {
    return bad_url(url, "empty");
  }
  if (url.starts_with(kSqlite)) {
    return parse_sqlite(url);
  }
  if (url.starts_with("postgresql://") || url.starts_with("postgres://")) {
    StoreUrl out;
    out.backend = Backend::postgresql;
    out.target = with_pg_defaults(url);
    return out;
  }
  return bad_url(url, "unknown scheme");
}

std::string redact_url(std::string_view url) {
  std::string out{url};
  // scheme://user:password@host → scheme://user:***@host
  if (const auto scheme = out.find("://"); scheme != std::string::npos) {
    const auto at = out.find('@', scheme + 3);
    const auto colon = out.find(':', scheme + 3);
    if (at != std::string::npos && colon != std::string::npos && colon < at) {
      out.replace(colon + 1, at - colon - 1, "***");
    }
  }
  // ...?password=secret&... → ...?password=***&...
  for (auto p = out.find("password="); p != std::string::npos; p = out.find("password=", p + 1)) {
    const auto start = p + 9;
    const auto end = out.find('&', start);
    out.replace(start, (end == std::string::npos ? out.size() : end) - start, "***");
  }
  return out;
}

}  // namespace sf::historian::detail
