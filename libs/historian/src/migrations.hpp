// Versioned schema migrations, shared by both back ends: an ordered list of
// SQL scripts, each applied once in its own transaction and recorded in the
// table schema_migrations (version, description, applied_at).
#pragma once

#include <functional>
#include <optional>
#include <span>
#include <string_view>

#include "sf/core/result.hpp"

namespace sf::historian::detail {

// The newest schema version; both back ends keep their migrations in step.
inline constexpr int kSchemaVersion = 2;

struct Migration {
  int version;
  std::string_view description;
  std::string_view sql;  // statements separated by ';'
};

// What a back end provides to the runner.
struct MigrationTarget {
  std::string_view backend;
  // The highest version recorded (0 for a new database).
  std::function<Result<int>()> current;
  // Runs the migration's SQL and records it, in one transaction that holds
  // the back end's write lock, and does nothing when another process applied
  // the same version meanwhile (two programs opening a new database at once).
  std::function<Status(const Migration&)> apply;
};

// Applies the pending migrations in order, up to `target` (the newest when
// empty). A database newer than this build is refused: an older program must
// not write into a schema it does not know.
Status run_migrations(std::span<const Migration> migrations, const MigrationTarget& target,
                      std::optional<int> up_to);

}  // namespace sf::historian::detail
