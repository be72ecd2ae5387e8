// The users file: users with password hashes or certificate thumbprints, roles, node patterns.
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cctype>
#include <fstream>

#include <fmt/format.h>

#include "openssl.hpp"
#include "sf/core/config.hpp"
#include "sf/core/text.hpp"
#include "sf/opcua/security/certificate.hpp"
#include "sf/opcua/security/users.hpp"
#include "sf/opcua/status_codes.hpp"

namespace sf::opcua::security {
namespace {

constexpr std::string_view kNs0 = "http://opcfoundation.org/UA/";

std::vector<Role> make_builtin_roles() {
  const std::string outside_ns0 = "!nsu=" + std::string(kNs0) + ";*";
  return {
      Role{"viewer", {"*"}, {}, {}},
      Role{"operator", {"*"}, {outside_ns0, "*"}, {outside_ns0, "*"}},
      Role{"engineer", {"*"}, {"*"}, {"*"}},
      // The cloud's web roles (libs/dashboard sessions.hpp): a consumer orders through the web
      // only and reads nothing on a server; an admin may all an engineer may.
      Role{"consumer", {}, {}, {}},
      Role{"admin", {"*"}, {"*"}, {"*"}},
  };
}

Status check_pattern(const config::Node& where, std::string_view pattern) {
  const std::string_view body = !pattern.empty() && pattern[0] == '!' ? pattern.substr(1) : pattern;
  if (body.empty() || body.substr(0, 3) == "ns=") {
    return where.error(
        fmt::format("pattern '{}': use '*', 'nsu=URI;...' or a namespace-0 id like 'i=2258'", pattern));
  }
  return {};
}

Result<std::vector<std::string>> read_patterns(const config::Node& role, std::string_view key) {
  if (!role.has(key)) {
    return std::vector<std::string>{};
  }
  auto child = role.child(key);
  auto list = child ? child->as<std::vector<std::string>>() : Result<std::vector<std::string>>(child.error());
  if (!list) {
    return list.error();
  }
  for (auto& pattern : *list) {
    SF_TRY(check_pattern(*child, pattern));
    pattern = canonical_pattern(pattern);
  }
  return list;
}

Result<Role> read_role(const config::Node& node, std::string name) {
  Role role;
  role.name = std::move(name);
  auto read = read_patterns(node, "read");
  auto write = read_patterns(node, "write");
  auto call = read_patterns(node, "call");
  for (auto* r : {&read, &write, &call}) {
    if (!*r) {
      return r->error();
    }
  }
  role.read = std::move(*read);
  role.write = std::move(*write);
  role.call = std::move(*call);
  return role;
}

Result<User> read_user(const config::Node& node) {
  User user;
  auto name = node.get<std::string>("name");
  auto password = node.get_or<std::string>("password", "");
  auto certificate = node.get_or<std::string>("certificate", "");
  auto roles = node.get_or<std::vector<std::string>>("roles", {});
  if (!name || !password || !certificate || !roles) {
    return !name          ? name.error()
           : !password    ? password.error()
           : !certificate ? certificate.error()
                          : roles.error();
  }
  if (password->empty() && certificate->empty()) {
    return node.error("a user needs a password hash or a certificate thumbprint");
  }
  if (!password->empty() && password->rfind("$scrypt$", 0) != 0) {
    return node.error("password: expected a hash made by `smartfactory opcua users add` ($scrypt$...)");
  }
  user.name = std::move(*name);
  user.password_hash = std::move(*password);
  user.certificate = lower(*certificate);
  user.roles = std::move(*roles);
  return user;
}

void emit_patterns(YAML::Emitter& out, std::string_view key, const std::vector<std::string>& patterns) {
  out << YAML::Key << std::string(key) << YAML::Value << YAML::Flow << YAML::BeginSeq;
  for (const auto& p : patterns) {
    out << YAML::DoubleQuoted << p;
  }
  out << YAML::EndSeq;
}

}  // namespace

const std::vector<std::string>& Role::patterns(Permission permission) const {
  switch (permission) {
    case Permission::Read:
      return read;
    case Permission::Write:
      return write;
    case Permission::Call:
      return call;
  }
  return read;
}

std::string canonical_pattern(std::string_view pattern) {
  const bool deny = !pattern.empty() && pattern[0] == '!';
  const std::string_view body = deny ? pattern.substr(1) : pattern;
  const bool ns0_id =
      body.size() > 2 && body[1] == '=' && std::string_view("isgb").find(body[0]) != std::string_view::npos;
  return std::string(deny ? "!" : "") + (ns0_id ? "nsu=" + std::string(kNs0) + ";" : std::string()) +
         std::string(body);
}

std::optional<bool> match_pattern(std::string_view pattern, std::string_view node) {
  const bool deny = !pattern.empty() && pattern[0] == '!';
  std::string_view body = deny ? pattern.substr(1) : pattern;
  bool matched = false;
  if (!body.empty() && body.back() == '*') {
    body.remove_suffix(1);
    matched = node.substr(0, body.size()) == body;
  } else {
    matched = node == body;
  }
  return matched ? std::optional<bool>(!deny) : std::nullopt;
}

bool allowed(const std::vector<std::string>& patterns, std::string_view node) {
  for (const auto& pattern : patterns) {
    if (auto decision = match_pattern(pattern, node)) {
      return *decision;
    }
  }
  return false;
}

const std::vector<Role>& UserDatabase::builtin_roles() {
  static const std::vector<Role> roles = make_builtin_roles();
  return roles;
}

UserDatabase::UserDatabase() {
  for (const auto& role : builtin_roles()) {
    roles_[role.name] = role;
  }
}

Result<UserDatabase> UserDatabase::load(const std::filesystem::path& file) {
  std::ifstream in(file);
  if (!in) {
    return make_error(Errc::io, fmt::format("cannot read the users file {}", file.string()));
  }
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  return parse(text, file.string());
}

Result<UserDatabase> UserDatabase::parse(std::string_view yaml, std::string name) {
  auto root = config::load_string(yaml, std::move(name));
  if (!root) {
    return root.error();
  }
  UserDatabase db;
  if (root->has("roles")) {
    auto roles = root->child("roles");
    auto keys = roles ? roles->keys() : Result<std::vector<std::string>>(roles.error());
    if (!keys) {
      return keys.error();
    }
    for (const auto& key : *keys) {
      auto role = read_role(*roles->child(key), key);
      if (!role) {
        return role.error();
      }
      db.roles_[key] = *role;
      db.custom_roles_[key] = std::move(*role);
    }
  }
  if (!root->has("users")) {
    return db;
  }
  auto users = root->child("users");
  auto items = users ? users->items() : Result<std::vector<config::Node>>(users.error());
  if (!items) {
    return items.error();
  }
  for (const auto& item : *items) {
    auto user = read_user(item);
    if (!user) {
      return user.error();
    }
    if (db.find(user->name) != nullptr) {
      return item.error(fmt::format("user '{}' appears twice", user->name));
    }
    for (const auto& role : user->roles) {
      if (db.role(role) == nullptr) {
        return item.error(fmt::format("unknown role '{}'", role));
      }
    }
    db.users_.push_back(std::move(*user));
  }
  return db;
}

std::string UserDatabase::to_yaml() const {
  YAML::Emitter out;
  out << YAML::BeginMap << YAML::Key << "users" << YAML::Value << YAML::BeginSeq;
  for (const auto& user : users_) {
    out << YAML::BeginMap << YAML::Key << "name" << YAML::Value << user.name;
    if (!user.password_hash.empty()) {
      out << YAML::Key << "password" << YAML::Value << YAML::DoubleQuoted << user.password_hash;
    }
    if (!user.certificate.empty()) {
      out << YAML::Key << "certificate" << YAML::Value << user.certificate;
    }
    out << YAML::Key << "roles" << YAML::Value << YAML::Flow << user.roles << YAML::EndMap;
  }
  out << YAML::EndSeq;
  if (!custom_roles_.empty()) {
    out << YAML::Key << "roles" << YAML::Value << YAML::BeginMap;
    for (const auto& [name, role] : custom_roles_) {
      out << YAML::Key << name << YAML::Value << YAML::BeginMap;
      emit_patterns(out, "read", role.read);
      emit_patterns(out, "write", role.write);
      emit_patterns(out, "call", role.call);
      out << YAML::EndMap;
    }
    out << YAML::EndMap;
  }
  out << YAML::EndMap;
  return std::string(out.c_str()) + "\n";
}

Status UserDatabase::save(const std::filesystem::path& file) const {
  const std::string text = to_yaml();
  return write_file(file, ByteSpan(reinterpret_cast<const std::uint8_t*>(text.data()), text.size()), true);
}

const User* UserDatabase::find(std::string_view name) const {
  const auto it = std::find_if(users_.begin(), users_.end(), [&](const User& u) { return u.name == name; });
  return it == users_.end() ? nullptr : &*it;
}

const User* UserDatabase::find_by_certificate(std::string_view thumbprint) const {
  const auto it = std::find_if(users_.begin(), users_.end(), [&](const User& u) {
    return !u.certificate.empty() && u.certificate == thumbprint;
  });
  return it == users_.end() ? nullptr : &*it;
}

const Role* UserDatabase::role(std::string_view name) const {
  const auto it = roles_.find(name);
  return it == roles_.end() ? nullptr : &it->second;
}

bool UserDatabase::has_password_users() const {
  return std::any_of(users_.begin(), users_.end(), [](const User& u) { return !u.password_hash.empty(); });
}

bool UserDatabase::has_certificate_users() const {
  return std::any_of(users_.begin(), users_.end(), [](const User& u) { return !u.certificate.empty(); });
}

Result<const User*> UserDatabase::authenticate(std::string_view name, std::string_view password) const {
  const User* user = find(name);
  if (user == nullptr || user->password_hash.empty()) {
    // The same work as for a real user, so the time does not tell who exists.
    static const std::string dummy = hash_password("not a user").value_or(std::string());
    (void)verify_password(password, dummy);
    return status_error(status::BadUserAccessDenied, fmt::format("unknown user '{}'", name));
  }
  if (!verify_password(password, user->password_hash)) {
    return status_error(status::BadUserAccessDenied, fmt::format("wrong password for user '{}'", name));
  }
  return user;
}

Status UserDatabase::put(User user) {
  for (const auto& role : user.roles) {
    if (this->role(role) == nullptr) {
      return make_error(Errc::invalid_argument, fmt::format("unknown role '{}'", role));
    }
  }
  user.certificate = lower(user.certificate);
  remove(user.name);
  users_.push_back(std::move(user));
  return {};
}

bool UserDatabase::remove(std::string_view name) {
  const auto before = users_.size();
  users_.erase(std::remove_if(users_.begin(), users_.end(), [&](const User& u) { return u.name == name; }),
               users_.end());
  return users_.size() != before;
}

}  // namespace sf::opcua::security
