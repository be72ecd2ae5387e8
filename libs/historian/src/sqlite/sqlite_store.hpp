// The SQLite back end: the embedded default (see sqlite_store.cpp).
#pragma once

#include <memory>

#include "sf/historian/store.hpp"
#include "url.hpp"

namespace sf::historian::sqlite {

Result<std::unique_ptr<Store>> open_store(const detail::StoreUrl& url, const StoreOptions& options);

}  // namespace sf::historian::sqlite
