// Per-module loggers over spdlog. Every module asks for its logger by name
// ("ethercat", "opcua", ...); one call sets the level for all of them.
#pragma once

#include <memory>
#include <string_view>

#include <spdlog/spdlog.h>

#include "sf/core/result.hpp"

namespace sf::log {

using Logger = std::shared_ptr<spdlog::logger>;

// The logger of a module, created on first use with the global level and
// sink (stderr). Cheap to call; cache it in hot paths.
Logger get(std::string_view module);

// Sets the level of every existing and future logger:
// trace, debug, info, warn, error, critical, off.
Status set_level(std::string_view level);

// Reads SF_LOG (e.g. "debug" or "info,ethercat=trace") once at start-up.
void init_from_env();

}  // namespace sf::log
