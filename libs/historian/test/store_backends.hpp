// The two back ends the store suite runs against, as GoogleTest type
// parameters: each makes a fresh, empty database URL, runs raw SQL on it and
// can make the database unavailable and available again (fault tests).
#pragma once

#include <filesystem>
#include <memory>
#include <string>

#include <gtest/gtest.h>

#include "sf/core/result.hpp"
#include "temp_dir.hpp"

namespace sf::historian::test {

// Every back end: url() of a fresh database (empty string + skip reason when
// the back end cannot run here), sql() on it, and break/repair for faults.
class Backend {
 public:
  virtual ~Backend() = default;
  [[nodiscard]] virtual std::string url() const = 0;
  virtual Result<std::string> sql(const std::string& statement) = 0;
  // The database stops answering writes (PostgreSQL: the server is killed;
  // SQLite: another connection holds the write lock), and comes back.
  virtual void make_unavailable() = 0;
  virtual void make_available() = 0;
};

struct SqliteBackend {
  static constexpr const char* kName = "sqlite";
  // Why it cannot run here (empty: it can).
  static std::string unavailable_reason() { return {}; }
  static std::unique_ptr<Backend> make();
};

struct PostgresBackend {
  static constexpr const char* kName = "postgresql";
  static std::string unavailable_reason();
  static std::unique_ptr<Backend> make();
};

using Backends = ::testing::Types<SqliteBackend, PostgresBackend>;

struct BackendNames {
  template <typename T>
  static std::string GetName(int /*index*/) {
    return T::kName;
  }
};

// In a typed fixture's SetUp: skips the test with the reason when the back end cannot run.
#define SF_REQUIRE_BACKEND(B)                                     \
  do {                                                            \
    if (const auto why = B::unavailable_reason(); !why.empty()) { \
      GTEST_SKIP() << B::kName << " half skipped: " << why;       \
    }                                                             \
  } while (false)

}  // namespace sf::historian::test
