#include "migrations.hpp"

#include <fmt/format.h>

#include "sf/core/log.hpp"

namespace sf::historian::detail {

Status run_migrations(std::span<const Migration> migrations, const MigrationTarget& target,
                      std::optional<int> up_to) {
  const int newest = migrations.empty() ? 0 : migrations.back().version;
  auto current = target.current();
  if (!current) {
    return current.error();
  }
  if (*current > newest) {
    return make_error(Errc::unsupported,
                      fmt::format("{} database has schema version {}, newer than this build knows ({}); "
                                  "use a newer smartfactory",
                                  target.backend, *current, newest));
  }
  for (const auto& m : migrations) {
    if (m.version <= *current || (up_to && m.version > *up_to)) {
      continue;
    }
    if (auto st = target.apply(m); !st) {
      return st.error().with_context(
          fmt::format("{} schema migration {} ({})", target.backend, m.version, m.description));
    }
    log::get("historian")
        ->info("{}: applied schema migration {} ({})", target.backend, m.version, m.description);
  }
  return {};
}

}  // namespace sf::historian::detail
