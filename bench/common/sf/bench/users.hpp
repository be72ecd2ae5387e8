// A users file (`smartfactory opcua users` format) with one password user: whom the dashboard
// benchmarks log in as. Cheap scrypt parameters: they time requests and pages, not logins.
// Header-only: its users link sf::opcua_security.
#pragma once

#include <filesystem>
#include <string>

#include "sf/core/result.hpp"
#include "sf/opcua/security/users.hpp"

namespace sf::bench {

inline Status write_users(const std::filesystem::path& file, const std::string& user,
                          const std::string& password, const std::string& role) {
  opcua::security::UserDatabase users;
  auto hash = opcua::security::hash_password(password, {10, 8, 1});
  if (!hash) {
    return hash.error();
  }
  SF_TRY(users.put({user, *hash, {}, {role}}));
  return users.save(file);
}

}  // namespace sf::bench
