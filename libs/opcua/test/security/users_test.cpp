// Password hashes, the users file and role patterns.
#include "sf/opcua/security/users.hpp"

#include <gtest/gtest.h>

#include "sf/opcua/status_codes.hpp"
#include "test_keys.hpp"

namespace sf::opcua::security::test {
namespace {

// Cheap parameters for tests; the format records them, so verification uses the same.
const PasswordHashParams kFast{10, 8, 1};

TEST(Passwords, HashesAreSaltedAndVerify) {
  auto a = hash_password("secret", kFast);
  auto b = hash_password("secret", kFast);
  ASSERT_TRUE(a.ok() && b.ok());
  EXPECT_NE(*a, *b);  // per-password salt
  EXPECT_EQ(a->rfind("$scrypt$ln=10,r=8,p=1$", 0), 0U);
  EXPECT_TRUE(verify_password("secret", *a));
  EXPECT_FALSE(verify_password("Secret", *a));
  EXPECT_FALSE(verify_password("", *a));
  EXPECT_FALSE(verify_password("secret", "$scrypt$ln=10,r=8,p=1$AAAA$AAAA"));
  EXPECT_FALSE(verify_password("secret", "plain-text-password"));
  EXPECT_FALSE(verify_password("secret", "$scrypt$ln=40,r=8,p=1$AAAA$AAAA"));  // absurd cost refused
  EXPECT_FALSE(hash_password("x", PasswordHashParams{30, 8, 1}).ok());
}

TEST(Roles, PatternsDecideInOrder) {
  const std::string counter = "nsu=urn:smartfactory:demo;s=Demo.Counter";
  EXPECT_EQ(match_pattern("*", counter), true);
  EXPECT_EQ(match_pattern("!*", counter), false);
  EXPECT_EQ(match_pattern("nsu=urn:smartfactory:demo;*", counter), true);
  EXPECT_EQ(match_pattern("nsu=urn:smartfactory:demo;s=Demo.Counter", counter), true);
  EXPECT_EQ(match_pattern("nsu=urn:smartfactory:demo;s=Demo.Count", counter), std::nullopt);
  EXPECT_EQ(match_pattern("nsu=urn:other;*", counter), std::nullopt);
  EXPECT_TRUE(allowed({"!nsu=urn:smartfactory:demo;s=Demo.Temperature", "*"}, counter));
  EXPECT_FALSE(allowed({"!nsu=urn:smartfactory:demo;s=Demo.C*", "*"}, counter));
  EXPECT_FALSE(allowed({}, counter));
  EXPECT_EQ(canonical_pattern("i=2258"), "nsu=http://opcfoundation.org/UA/;i=2258");
  EXPECT_EQ(canonical_pattern("!s=x"), "!nsu=http://opcfoundation.org/UA/;s=x");
  EXPECT_EQ(canonical_pattern("*"), "*");
}

TEST(Roles, BuiltinRoles) {
  const UserDatabase db;
  const std::string demo = "nsu=urn:smartfactory:demo;s=Demo.Counter";
  const std::string ns0 = "nsu=http://opcfoundation.org/UA/;i=2258";
  const Role* viewer = db.role("viewer");
  const Role* operator_role = db.role("operator");
  const Role* engineer = db.role("engineer");
  ASSERT_TRUE(viewer && operator_role && engineer);
  EXPECT_TRUE(allowed(viewer->read, demo));
  EXPECT_FALSE(allowed(viewer->write, demo));
  EXPECT_FALSE(allowed(viewer->call, demo));
  EXPECT_TRUE(allowed(operator_role->write, demo));
  EXPECT_TRUE(allowed(operator_role->call, demo));
  EXPECT_FALSE(allowed(operator_role->write, ns0));
  EXPECT_TRUE(allowed(engineer->write, ns0));
}

TEST(Users, FileRoundTripAndAuthentication) {
  UserDatabase db;
  ASSERT_TRUE(db.put(User{"alice", *hash_password("wonderland", kFast), "", {"operator"}}).ok());
  ASSERT_TRUE(db.put(User{"robot", "", "3f2aABCDEF", {"engineer", "viewer"}}).ok());
  EXPECT_FALSE(db.put(User{"eve", "", "", {"root"}}).ok());  // unknown role
  const std::string yaml = db.to_yaml();
  auto loaded = UserDatabase::parse(yaml);
  ASSERT_TRUE(loaded.ok()) << loaded.error().message << "\n" << yaml;
  ASSERT_EQ(loaded->users().size(), 2U);
  EXPECT_TRUE(loaded->has_password_users());
  EXPECT_TRUE(loaded->has_certificate_users());
  EXPECT_EQ(loaded->find_by_certificate("3f2aabcdef")->name, "robot");  // thumbprints in lower case
  EXPECT_EQ(loaded->find("robot")->roles, (std::vector<std::string>{"engineer", "viewer"}));

  auto ok = loaded->authenticate("alice", "wonderland");
  ASSERT_TRUE(ok.ok());
  EXPECT_EQ((*ok)->name, "alice");
  EXPECT_EQ(status_of(loaded->authenticate("alice", "wrong").error()), status::BadUserAccessDenied);
  EXPECT_EQ(status_of(loaded->authenticate("mallory", "wonderland").error()), status::BadUserAccessDenied);
  EXPECT_EQ(status_of(loaded->authenticate("robot", "").error()), status::BadUserAccessDenied);
  EXPECT_TRUE(loaded->remove("alice"));
  EXPECT_FALSE(loaded->remove("alice"));
}

TEST(Users, CustomRolesAndErrorsWithPlaces) {
  const std::string yaml = R"(users:
  - name: bob
    password: "$scrypt$ln=10,r=8,p=1$AAAAAAAAAAAAAAAAAAAAAA==$AAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAA="
    roles: [line-operator]
roles:
  line-operator:
    read: ["*"]
    write: ["nsu=urn:smartfactory:demo;s=Demo.Counter", "!*"]
    call: ["i=11492"]
)";
  auto db = UserDatabase::parse(yaml);
  ASSERT_TRUE(db.ok()) << db.error().message;
  const Role* role = db->role("line-operator");
  ASSERT_NE(role, nullptr);
  EXPECT_EQ(role->call, (std::vector<std::string>{"nsu=http://opcfoundation.org/UA/;i=11492"}));
  EXPECT_NE(db->to_yaml().find("line-operator"), std::string::npos);

  auto unknown_role =
      UserDatabase::parse("users:\n  - name: x\n    certificate: ab\n    roles: [boss]\n", "u.yaml");
  ASSERT_FALSE(unknown_role.ok());
  EXPECT_NE(unknown_role.error().message.find("u.yaml:2:"), std::string::npos)
      << unknown_role.error().message;
  auto plain = UserDatabase::parse("users:\n  - name: x\n    password: hunter2\n");
  ASSERT_FALSE(plain.ok());
  EXPECT_NE(plain.error().message.find("$scrypt$"), std::string::npos);
  auto index_pattern = UserDatabase::parse("roles:\n  r:\n    read: [\"ns=2;s=X\"]\n");
  EXPECT_FALSE(index_pattern.ok());
}

TEST(Users, SaveAndLoad) {
  TempDir dir;
  UserDatabase db;
  ASSERT_TRUE(db.put(User{"alice", *hash_password("wonderland", kFast), "", {"viewer"}}).ok());
  const auto file = dir.path() / "users.yaml";
  ASSERT_TRUE(db.save(file).ok());
  EXPECT_EQ((std::filesystem::status(file).permissions() & std::filesystem::perms::others_read),
            std::filesystem::perms::none);
  auto loaded = UserDatabase::load(file);
  ASSERT_TRUE(loaded.ok()) << loaded.error().message;
  EXPECT_TRUE(loaded->authenticate("alice", "wonderland").ok());
  EXPECT_FALSE(UserDatabase::load(dir.path() / "missing.yaml").ok());
}

// A running server sees users added or removed (`opcua users add` replaces the file) at the next
// login; a file that stops parsing keeps the users last read.
TEST(Users, FileIsReReadWhenItChanges) {
  TempDir dir;
  const auto file = dir.path() / "users.yaml";
  UserDatabase db;
  ASSERT_TRUE(db.put(User{"alice", *hash_password("wonderland", kFast), "", {"viewer"}}).ok());
  ASSERT_TRUE(db.save(file).ok());
  auto users = UsersFile::open(file);
  ASSERT_TRUE(users.ok()) << users.error().message;
  const auto first = (*users)->current();
  EXPECT_EQ((*users)->current(), first);  // unchanged: the same users, not read again
  EXPECT_EQ(first->find("bob"), nullptr);

  ASSERT_TRUE(db.put(User{"bob", *hash_password("builder", kFast), "", {"operator"}}).ok());
  ASSERT_TRUE(db.save(file).ok());
  const auto second = (*users)->current();
  ASSERT_NE(second->find("bob"), nullptr);
  EXPECT_TRUE(second->authenticate("bob", "builder").ok());
  EXPECT_EQ(first->find("bob"), nullptr);  // what a caller holds does not change under it

  const std::string broken = "users: [ {name: carol";
  ASSERT_TRUE(
      write_file(file, ByteSpan(reinterpret_cast<const std::uint8_t*>(broken.data()), broken.size()), true)
          .ok());
  EXPECT_EQ((*users)->current(), second);

  ASSERT_TRUE(db.remove("alice"));
  ASSERT_TRUE(db.save(file).ok());
  EXPECT_EQ((*users)->current()->find("alice"), nullptr);
  std::filesystem::remove(file);
  EXPECT_NE((*users)->current()->find("bob"), nullptr);
  EXPECT_FALSE(UsersFile::open(dir.path() / "missing.yaml").ok());
}

}  // namespace
}  // namespace sf::opcua::security::test
