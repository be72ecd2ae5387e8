// Store URLs: which back end, where, and the back end's own parameters.
#pragma once

#include <map>
#include <string>
#include <string_view>

#include "sf/core/result.hpp"

namespace sf::historian::detail {

enum class Backend { sqlite, postgresql };

struct StoreUrl {
  Backend backend = Backend::sqlite;
  // SQLite: the file path (":memory:" for an in-memory database).
  // PostgreSQL: the URI as libpq takes it, our defaults added.
  std::string target;
  // SQLite only: the parameters after '?' (busy_timeout_ms, synchronous).
  std::map<std::string, std::string> params;
};

// sqlite:PATH[?k=v&...] | sqlite::memory: | postgresql://... | postgres://...
Result<StoreUrl> parse_store_url(std::string_view url);

// The URL with any password replaced by "***", for messages and logs.
std::string redact_url(std::string_view url);

}  // namespace sf::historian::detail
