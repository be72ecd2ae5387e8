#include "sf/factory/machine.hpp"

#include <cmath>

#include <fmt/format.h>

namespace sf::factory {

std::optional<double> Operation::param(std::string_view name) const {
  auto it = params.find(std::string(name));
  if (it == params.end()) {
    return std::nullopt;
  }
  return it->second;
}

Result<std::int64_t> Operation::integer(std::string_view name, std::int64_t lo, std::int64_t hi) const {
  auto v = param(name);
  if (!v) {
    return make_error(Errc::invalid_argument, fmt::format("{} needs the parameter '{}'", type, name));
  }
  if (!std::isfinite(*v) || std::trunc(*v) != *v) {
    return make_error(Errc::invalid_argument,
                      fmt::format("{}: '{}' = {} is not a whole number", type, name, *v));
  }
  if (*v < static_cast<double>(lo) || *v > static_cast<double>(hi)) {
    return make_error(Errc::invalid_argument,
                      fmt::format("{}: '{}' = {} is outside {}..{}", type, name, *v, lo, hi));
  }
  return static_cast<std::int64_t>(*v);
}

}  // namespace sf::factory
