// Store URLs, and what a bad or unreachable one gives: a clear error, no crash.
#include <fstream>

#include <gtest/gtest.h>

#include "sf/historian/store.hpp"
#include "temp_dir.hpp"
#include "url.hpp"

namespace sf::historian {
namespace {

using detail::Backend;
using detail::parse_store_url;

TEST(StoreUrl, SqliteForms) {
  auto u = parse_store_url("sqlite:/var/lib/sf/history.db?busy_timeout_ms=100");
  ASSERT_TRUE(u.ok());
  EXPECT_EQ(u->backend, Backend::sqlite);
  EXPECT_EQ(u->target, "/var/lib/sf/history.db");
  EXPECT_EQ(u->params.at("busy_timeout_ms"), "100");
  EXPECT_EQ(parse_store_url("sqlite:///tmp/h.db")->target, "/tmp/h.db");
  EXPECT_EQ(parse_store_url("sqlite:relative.db")->target, "relative.db");
  EXPECT_EQ(parse_store_url("sqlite::memory:")->target, ":memory:");
}

TEST(StoreUrl, PostgresGetsTimeoutsUnlessGiven) {
  auto u = parse_store_url("postgresql://sf@db:5432/plant");
  ASSERT_TRUE(u.ok());
  EXPECT_EQ(u->backend, Backend::postgresql);
  EXPECT_EQ(u->target, "postgresql://sf@db:5432/plant?connect_timeout=5&tcp_user_timeout=30000");
  EXPECT_EQ(parse_store_url("postgres://db/plant?connect_timeout=1")->target,
            "postgres://db/plant?connect_timeout=1&tcp_user_timeout=30000");
}

TEST(StoreUrl, BadOnesSayWhatIsExpected) {
  for (const char* bad :
       {"", "mysql://db/x", "sqlite:", "sqlite:/x.db?cache=big", "sqlite:/x.db?oops", "/tmp/x.db"}) {
    auto u = parse_store_url(bad);
    ASSERT_FALSE(u.ok()) << bad;
    EXPECT_EQ(u.error().code, Errc::invalid_argument) << bad;
    EXPECT_NE(u.error().message.find("expected sqlite:PATH or postgresql://"), std::string::npos)
        << u.error().message;
  }
}

TEST(StoreUrl, PasswordsAreRedacted) {
  EXPECT_EQ(detail::redact_url("postgresql://sf:secret@db/x"), "postgresql://sf:***@db/x");
  EXPECT_EQ(detail::redact_url("postgresql://db/x?password=secret&sslmode=require"),
            "postgresql://db/x?password=***&sslmode=require");
  auto u = parse_store_url("mysql://sf:secret@db/x");
  EXPECT_EQ(u.error().message.find("secret"), std::string::npos);
}

TEST(OpenStore, BadSqliteParametersAreRefused) {
  auto s = open_store("sqlite::memory:?synchronous=sometimes");
  ASSERT_FALSE(s.ok());
  EXPECT_EQ(s.error().code, Errc::invalid_argument);
  EXPECT_NE(s.error().message.find("synchronous"), std::string::npos);
}

TEST(OpenStore, AnUnreachableSqliteFileIsAnIoError) {
  auto s = open_store("sqlite:/nonexistent-directory/history.db");
  ASSERT_FALSE(s.ok());
  EXPECT_EQ(s.error().code, Errc::io);
  EXPECT_NE(s.error().message.find("/nonexistent-directory/history.db"), std::string::npos)
      << s.error().message;
}

TEST(OpenStore, AFileThatIsNoDatabaseIsMalformed) {
  test::TempDir dir;
  const auto path = dir.path() / "not.db";
  std::ofstream(path) << "this is not an SQLite database, it is a text file of some length......";
  auto s = open_store("sqlite:" + path.string());
  ASSERT_FALSE(s.ok());
  EXPECT_EQ(s.error().code, Errc::malformed) << s.error().describe();
}

TEST(OpenStore, AnUnreachablePostgresIsAnIoErrorSoon) {
  // Port 1 on the loopback: nothing listens, the connection is refused at once.
  auto s = open_store("postgresql://sf@127.0.0.1:1/plant");
  ASSERT_FALSE(s.ok());
  EXPECT_EQ(s.error().code, Errc::io);
  EXPECT_NE(s.error().message.find("unreachable"), std::string::npos) << s.error().message;
}

TEST(OpenStore, AMalformedPostgresUrlIsABadUrl) {
  auto s = open_store("postgresql://sf@db/plant?no_such_option=1");
  ASSERT_FALSE(s.ok());
  EXPECT_EQ(s.error().code, Errc::invalid_argument) << s.error().describe();
  EXPECT_NE(s.error().message.find("no_such_option"), std::string::npos) << s.error().message;
}

}  // namespace
}  // namespace sf::historian
