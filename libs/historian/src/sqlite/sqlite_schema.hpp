// The SQLite schema and its migrations (see migrations.hpp).
#pragma once

#include <optional>

#include "sf/core/result.hpp"
#include "sqlite/sqlite_db.hpp"

namespace sf::historian::sqlite {

// Brings the database to `up_to` (the newest version when empty).
Status migrate(Db& db, std::optional<int> up_to);
Result<int> schema_version(Db& db);

}  // namespace sf::historian::sqlite
