#include "sf/factory/machine.hpp"

namespace sf::factory {

std::optional<double> Operation::param(std::string_view name) const {
  auto it = params.find(std::string(name));
  if (it == params.end()) {
    return std::nullopt;
  }
  return it->second;
}

}  // namespace sf::factory
