// The logger the UA-TCP and secure channel code writes to (internal).
#pragma once

#include "sf/core/log.hpp"

namespace sf::opcua::detail {

inline const sf::log::Logger& logger() {
  static const auto log = sf::log::get("opcua");
  return log;
}

}  // namespace sf::opcua::detail
