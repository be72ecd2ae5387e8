#include "store_backends.hpp"

#include <atomic>

#include <fmt/format.h>
#include <sqlite3.h>

#include "pg_server.hpp"

namespace sf::historian::test {

namespace {

// --- SQLite --------------------------------------------------------------------

class Sqlite final : public Backend {
 public:
  // A short busy timeout, so a locked database is reported after 50 ms.
  [[nodiscard]] std::string url() const override {
    return fmt::format("sqlite:{}?busy_timeout_ms=50", (dir_.path() / "history.db").string());
  }

  Result<std::string> sql(const std::string& statement) override {
    sqlite3* db = nullptr;
    sqlite3_open((dir_.path() / "history.db").c_str(), &db);
    std::string out;
    char* message = nullptr;
    const int rc = sqlite3_exec(
        db, statement.c_str(),
        [](void* text, int n, char** values, char** /*names*/) {
          auto& s = *static_cast<std::string*>(text);
          for (int i = 0; i < n; ++i) {
            s += (i != 0 ? "|" : "") + std::string{values[i] != nullptr ? values[i] : ""};
          }
          s += "\n";
          return 0;
        },
        &out, &message);
    std::string error = message != nullptr ? message : "";
    sqlite3_free(message);
    sqlite3_close(db);
    if (rc != SQLITE_OK) {
      return make_error(Errc::state, error);
    }
    return out;
  }

  void make_unavailable() override {
    sqlite3_open((dir_.path() / "history.db").c_str(), &locker_);
    sqlite3_busy_timeout(locker_, 10'000);  // wait for a write in progress to end
    ASSERT_EQ(sqlite3_exec(locker_, "BEGIN EXCLUSIVE", nullptr, nullptr, nullptr), SQLITE_OK);
  }

  void make_available() override {
    sqlite3_exec(locker_, "COMMIT", nullptr, nullptr, nullptr);
    sqlite3_close(locker_);
    locker_ = nullptr;
  }

  ~Sqlite() override { sqlite3_close(locker_); }

 private:
  TempDir dir_;
  sqlite3* locker_ = nullptr;
};

// --- PostgreSQL ------------------------------------------------------------------

// One server per test binary, started on first use; every test gets its own database.
struct SharedServer {
  std::unique_ptr<testing::PgServer> server;
  std::string error;
  bool missing = false;
};

SharedServer& shared() {
  static SharedServer s = [] {
    SharedServer out;
    if (!testing::PgServer::find_bin_dir()) {
      out.missing = true;
      out.error = "PostgreSQL binaries not found (scripts/setup installs the postgresql package)";
      return out;
    }
    auto server = testing::PgServer::start();
    if (server) {
      out.server = std::move(*server);
    } else {
      out.error = server.error().describe();
    }
    return out;
  }();
  return s;
}

class Postgres final : public Backend {
 public:
  Postgres() {
    static std::atomic<int> counter{0};
    name_ = fmt::format("t{}", ++counter);
    auto st = shared().server->create_database(name_);
    EXPECT_TRUE(st.ok()) << st.error().describe();
  }

  [[nodiscard]] std::string url() const override { return shared().server->url(name_); }

  Result<std::string> sql(const std::string& statement) override {
    return shared().server->psql(name_, statement);
  }

  void make_unavailable() override {
    auto st = shared().server->kill();
    ASSERT_TRUE(st.ok()) << st.error().describe();
  }

  void make_available() override {
    auto st = shared().server->restart();
    ASSERT_TRUE(st.ok()) << st.error().describe();
  }

  ~Postgres() override {
    if (!shared().server->running()) {
      (void)shared().server->restart();
    }
  }

 private:
  std::string name_;
};

}  // namespace

std::unique_ptr<Backend> SqliteBackend::make() {
  return std::make_unique<Sqlite>();
}

std::string PostgresBackend::unavailable_reason() {
  auto& s = shared();
  if (s.server) {
    return {};
  }
  // Installed but not startable is a failure, not a skip: CI installs it.
  if (!s.missing) {
    ADD_FAILURE() << "PostgreSQL is installed but the test server did not start: " << s.error;
  }
  return s.error;
}

std::unique_ptr<Backend> PostgresBackend::make() {
  return std::make_unique<Postgres>();
}

}  // namespace sf::historian::test
