// A temporary directory for a test, removed with everything in it.
#pragma once

#include <stdlib.h>

#include <filesystem>

namespace sf::historian::test {

class TempDir {
 public:
  TempDir() {
    char tmpl[] = "/tmp/sf-hist-XXXXXX";
    path_ = ::mkdtemp(tmpl) != nullptr ? std::filesystem::path{tmpl} : std::filesystem::path{};
  }
  ~TempDir() {
    std::error_code ec;
    std::filesystem::remove_all(path_, ec);
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  [[nodiscard]] const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
};

}  // namespace sf::historian::test
