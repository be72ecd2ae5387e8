// `smartfactory opcua users add|remove|list FILE`: the users file of `opcua server --users`
// (salted scrypt password hashes or certificate thumbprints, and roles; see
// sf/opcua/security/users.hpp).
#include <filesystem>
#include <iostream>
#include <memory>

#include <fmt/format.h>

#include "commands.hpp"
#include "opcua_security.hpp"
#include "sf/opcua/security/certificate.hpp"
#include "sf/opcua/security/users.hpp"

namespace sf::app {
namespace {

namespace sec = sf::opcua::security;

struct UsersOptions {
  std::string file;
  std::string name;
  std::vector<std::string> roles;
  std::string password_file;
  std::string certificate;
};

// The file's users, or none when it does not exist yet.
Result<sec::UserDatabase> open_file(const std::string& file) {
  std::error_code ec;
  if (!std::filesystem::exists(file, ec)) {
    return sec::UserDatabase();
  }
  return sec::UserDatabase::load(file);
}

int users_fail(const char* command, const Error& error) {
  std::cerr << "opcua users " << command << ": " << error.message << "\n";
  return kExitFailure;
}

int run_add(const UsersOptions& o) {
  auto db = open_file(o.file);
  if (!db) {
    return users_fail("add", db.error());
  }
  sec::User user;
  user.name = o.name;
  user.roles = o.roles;
  if (!o.certificate.empty()) {
    auto der = sec::read_certificate_file(o.certificate);
    auto info = der ? sec::inspect_certificate(der->span()) : Result<sec::CertificateInfo>(der.error());
    if (!info) {
      return users_fail("add", info.error());
    }
    user.certificate = info->thumbprint;
  } else {
    auto password = read_password(o.password_file, fmt::format("New password for {}: ", o.name));
    if (!password || password->empty()) {
      return users_fail("add",
                        password ? make_error(Errc::invalid_argument, "empty password") : password.error());
    }
    auto hash = sec::hash_password(*password);
    if (!hash) {
      return users_fail("add", hash.error());
    }
    user.password_hash = std::move(*hash);
  }
  if (auto st = db->put(std::move(user)); !st) {
    return users_fail("add", st.error());
  }
  if (auto st = db->save(o.file); !st) {
    return users_fail("add", st.error());
  }
  std::printf("%s: %s (%zu users)\n", o.file.c_str(), o.name.c_str(), db->users().size());
  return kExitOk;
}

int run_remove(const UsersOptions& o) {
  auto db = open_file(o.file);
  if (!db) {
    return users_fail("remove", db.error());
  }
  if (!db->remove(o.name)) {
    return users_fail("remove",
                      make_error(Errc::not_found, fmt::format("no user '{}' in {}", o.name, o.file)));
  }
  if (auto st = db->save(o.file); !st) {
    return users_fail("remove", st.error());
  }
  return kExitOk;
}

int run_list(const UsersOptions& o) {
  auto db = open_file(o.file);
  if (!db) {
    return users_fail("list", db.error());
  }
  for (const auto& user : db->users()) {
    std::string roles;
    for (const auto& role : user.roles) {
      roles += (roles.empty() ? "" : ",") + role;
    }
    std::printf("%-20s %-9s %s%s\n", user.name.c_str(), roles.c_str(),
                user.password_hash.empty() ? "" : "password",
                user.certificate.empty() ? "" : (" certificate " + user.certificate).c_str());
  }
  return kExitOk;
}

}  // namespace

void register_opcua_users(CLI::App& group, CommandResult& result) {
  auto* users =
      group.add_subcommand("users", "The users file of `opcua server --users`: passwords and roles");
  users->require_subcommand(1);
  users->footer(
      "Roles: viewer (read), operator (read; write and call outside namespace 0), engineer (everything),\n"
      "or roles of the file's own `roles:` section (node patterns for read, write and call).");
  auto o = std::make_shared<UsersOptions>();

  auto* add = users->add_subcommand("add", "Add or replace a user (password asked for, or from a file)");
  add->add_option("file", o->file, "Users file (created when missing)")->required();
  add->add_option("name", o->name, "User name")->required();
  add->add_option("--role", o->roles, "Role (repeatable)")->required();
  add->add_option("--password-file", o->password_file, "Take the password from this file's first line");
  add->add_option("--certificate", o->certificate, "Log in with this X.509 certificate instead of a password")
      ->excludes("--password-file");
  add->callback([o, &result] { result.exit_code = run_add(*o); });

  auto* remove = users->add_subcommand("remove", "Remove a user");
  remove->add_option("file", o->file, "Users file")->required();
  remove->add_option("name", o->name, "User name")->required();
  remove->callback([o, &result] { result.exit_code = run_remove(*o); });

  auto* list = users->add_subcommand("list", "List the users and their roles");
  list->add_option("file", o->file, "Users file")->required();
  list->callback([o, &result] { result.exit_code = run_list(*o); });
}

}  // namespace sf::app
