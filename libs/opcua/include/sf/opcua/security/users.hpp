// Users and roles of a server (OPC 10000-4 §5.6.3 user identity tokens, OPC 10000-3 §4.8 roles):
// a YAML file of users with salted password hashes (scrypt) or X.509 certificates, each with
// roles; roles grant read, write and call permissions on nodes by pattern.
//
//   users:
//     - name: alice
//       password: $scrypt$ln=15,r=8,p=1$<salt>$<hash>    # `smartfactory opcua users add`
//       roles: [operator]
//     - name: cell-3-robot
//       certificate: 3f2a...                             # SHA-1 thumbprint of its certificate
//       roles: [engineer]
//   roles:                                               # optional: replaces a built-in role
//     operator:
//       read:  ["*"]
//       write: ["nsu=urn:smartfactory:demo;s=Demo.Counter", "!*"]
//       call:  ["nsu=urn:smartfactory:demo;*"]
//
// Patterns are node ids in text with the namespace as URI ("nsu=URI;s=Name", "i=2258" for
// namespace 0); a trailing '*' matches any rest; a leading '!' denies. The first pattern that
// matches decides, none means no. Built-in roles: viewer (read), operator (read; write and
// call outside namespace 0), engineer and admin (everything), consumer (nothing on a server: the
// web's role of people who order boxes).
#pragma once

#include <filesystem>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "sf/core/result.hpp"

namespace sf::opcua::security {

// scrypt (RFC 7914) with a random 16-byte salt per password.
struct PasswordHashParams {
  unsigned log2_n = 15;  // N = 2^15: 32 MiB and tens of milliseconds per check
  unsigned r = 8;
  unsigned p = 1;
};
// "$scrypt$ln=15,r=8,p=1$<salt base64>$<hash base64>".
Result<std::string> hash_password(std::string_view password, PasswordHashParams params = {});
// Constant-time comparison; false for malformed hashes too.
bool verify_password(std::string_view password, std::string_view encoded);

enum class Permission { Read, Write, Call };

struct Role {
  std::string name;
  std::vector<std::string> read;
  std::vector<std::string> write;
  std::vector<std::string> call;

  [[nodiscard]] const std::vector<std::string>& patterns(Permission permission) const;
};

// Does `node` ("nsu=URI;s=..." as canonical_node_text makes it) match `pattern`? nullopt when
// the pattern does not speak about the node, else allow (true) or deny (false).
std::optional<bool> match_pattern(std::string_view pattern, std::string_view node);
// The first deciding pattern of a list; false when none matches.
bool allowed(const std::vector<std::string>& patterns, std::string_view node);
// "i=2258" → "nsu=http://opcfoundation.org/UA/;i=2258"; other texts unchanged.
std::string canonical_pattern(std::string_view pattern);

struct User {
  std::string name;
  std::string password_hash;  // empty: no password login
  std::string certificate;    // SHA-1 thumbprint (hex) of an X.509 user certificate; empty: none
  std::vector<std::string> roles;
};

class UserDatabase {
 public:
  // The built-in roles only, no users.
  UserDatabase();

  static Result<UserDatabase> load(const std::filesystem::path& file);
  static Result<UserDatabase> parse(std::string_view yaml, std::string name = "<users>");
  [[nodiscard]] std::string to_yaml() const;
  Status save(const std::filesystem::path& file) const;

  [[nodiscard]] const User* find(std::string_view name) const;
  [[nodiscard]] const User* find_by_certificate(std::string_view thumbprint) const;
  [[nodiscard]] const Role* role(std::string_view name) const;
  [[nodiscard]] const std::vector<User>& users() const { return users_; }
  [[nodiscard]] bool has_password_users() const;
  [[nodiscard]] bool has_certificate_users() const;

  // BadUserAccessDenied for an unknown user or a wrong password (indistinguishable, also in
  // time); the user otherwise.
  Result<const User*> authenticate(std::string_view name, std::string_view password) const;

  // Adds or replaces a user; unknown roles → Errc::invalid_argument.
  Status put(User user);
  bool remove(std::string_view name);

  static const std::vector<Role>& builtin_roles();

 private:
  std::vector<User> users_;
  std::map<std::string, Role, std::less<>> roles_;
  std::map<std::string, Role, std::less<>> custom_roles_;  // from the file (written back by save)
};

// The users file of a running server, re-read when it changes (inode, size or modification time:
// `opcua users add` replaces the file), as the PKI folders are, so that a user added or removed
// counts from the next login without a restart. Sessions already activated keep their roles.
// Thread-safe.
class UsersFile {
 public:
  // Reads the file; a server refuses to start with a missing or broken one.
  static Result<std::shared_ptr<UsersFile>> open(std::filesystem::path file);

  // The users as the file says now. A file that no longer reads or parses leaves the last good
  // users in force (the log says why).
  std::shared_ptr<const UserDatabase> current();
  [[nodiscard]] const std::filesystem::path& path() const { return file_; }

 private:
  explicit UsersFile(std::filesystem::path file) : file_(std::move(file)) {}
  [[nodiscard]] std::string stamp() const;

  std::filesystem::path file_;
  std::mutex mutex_;
  std::string stamp_;  // of the file current() last looked at
  std::shared_ptr<const UserDatabase> users_;
};

}  // namespace sf::opcua::security
