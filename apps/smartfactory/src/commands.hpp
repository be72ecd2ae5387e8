// Command groups of the smartfactory CLI. Each group's file registers its
// subcommands on the app; the group's module does the work.
#pragma once

#include <CLI/CLI.hpp>

namespace sf::app {

// Exit codes shared by all commands.
inline constexpr int kExitOk = 0;
inline constexpr int kExitFailure = 1;
inline constexpr int kExitUsage = 2;

}  // namespace sf::app
