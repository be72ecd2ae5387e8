// A throwaway PostgreSQL server for tests and benchmarks: initdb in a fresh
// temporary directory, postgres on a free port of 127.0.0.1, trust
// authentication for user "sf". initdb and postgres refuse to run as root, so
// as root both run as the "postgres" user (setpriv). The server is our child
// with a parent-death signal, so it goes away with the test even on a crash.
// That signal follows the *thread* that started the server: call start() and
// restart() from a thread that lives as long as the server should (the main
// thread); kill() may come from any thread.
#pragma once

#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "sf/core/process.hpp"
#include "sf/core/result.hpp"

namespace sf::historian::testing {

struct PgServerOptions {
  // fsync off (tests): a killed server still keeps what it committed, since
  // the OS has it; only a power cut would lose it.
  bool durable = false;
};

class PgServer {
 public:
  // The directory holding initdb/postgres: $SF_PG_BIN, else the newest
  // /usr/lib/postgresql/<version>/bin. nullopt when PostgreSQL is not installed.
  static std::optional<std::filesystem::path> find_bin_dir();

  static Result<std::unique_ptr<PgServer>> start(PgServerOptions options = {});
  ~PgServer();
  PgServer(const PgServer&) = delete;
  PgServer& operator=(const PgServer&) = delete;

  // postgresql://sf@127.0.0.1:PORT/DATABASE
  [[nodiscard]] std::string url(std::string_view database = "postgres") const;
  [[nodiscard]] int port() const { return port_; }
  [[nodiscard]] const std::filesystem::path& bin_dir() const { return bin_; }

  Status create_database(std::string_view name);
  // Runs SQL with psql against `database` and returns its unaligned output.
  Result<std::string> psql(std::string_view database, std::string_view sql);
  // Immediate shutdown (SIGQUIT): no checkpoint, like a crash; restarting
  // runs WAL recovery.
  Status kill();
  // Starts it again on the same port and data directory.
  Status restart();
  [[nodiscard]] bool running() const { return server_.pid() > 0; }

 private:
  PgServer() = default;
  Status launch();
  Result<std::string> run_tool(const std::vector<std::string>& argv, bool as_server_user);

  std::filesystem::path bin_;
  std::filesystem::path dir_;
  PgServerOptions options_;
  int port_ = 0;
  Process server_;
  bool as_postgres_ = false;
};

}  // namespace sf::historian::testing
