// node-opcua peers of the unit tests (tests/peers/opcua/*.mjs): where the repository is, and why
// they cannot run here. Shared by the modules' tests (sf::core_testing, linked by sf_unit_test).
#pragma once

#include <cstdlib>
#include <filesystem>
#include <optional>
#include <string>

#include "sf/core/process.hpp"

namespace sf::testing {

// The repository: $SF_SOURCE_DIR (set for every unit test by sf_unit_test).
inline std::filesystem::path source_dir() {
  const char* env = std::getenv("SF_SOURCE_DIR");  // NOLINT(concurrency-mt-unsafe): no thread sets it
  return env != nullptr ? std::filesystem::path(env) : std::filesystem::current_path();
}

inline std::optional<std::filesystem::path> find_node() {
  return find_program("node");
}

// Why node-opcua tests cannot run here, or nullopt if they can.
inline std::optional<std::string> node_unavailable() {
  if (!find_node()) {
    return "node is not on PATH";
  }
  if (!std::filesystem::exists(source_dir() / "node_modules" / "node-opcua")) {
    return "node_modules/node-opcua is missing (npm ci)";
  }
  return std::nullopt;
}

}  // namespace sf::testing
