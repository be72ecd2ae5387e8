#include "sf/historian/store.hpp"

#include "migrations.hpp"
#include "postgres/pg_store.hpp"
#include "sqlite/sqlite_store.hpp"
#include "url.hpp"

namespace sf::historian {

Result<std::unique_ptr<Store>> open_store(std::string_view url, const StoreOptions& options) {
  auto parsed = detail::parse_store_url(url);
  if (!parsed) {
    return parsed.error();
  }
  if (options.partition_width.count() <= 0) {
    return make_error(Errc::invalid_argument, "partition width must be positive");
  }
  switch (parsed->backend) {
    case detail::Backend::sqlite:
      return sqlite::open_store(*parsed, options);
    case detail::Backend::postgresql:
      return postgres::open_store(*parsed, options);
  }
  return make_error(Errc::unsupported, "unknown store back end");
}

int latest_schema_version() {
  return detail::kSchemaVersion;
}

}  // namespace sf::historian
