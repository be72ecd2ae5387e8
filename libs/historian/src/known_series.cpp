#include "known_series.hpp"

#include <fmt/format.h>

namespace sf::historian::detail {

Status validate(const SeriesInfo& info) {
  if (info.server.empty() || info.node_id.empty()) {
    return make_error(Errc::invalid_argument, "a series needs a server and a node id");
  }
  if (to_string(info.data_type) == "unknown") {
    return make_error(Errc::invalid_argument, fmt::format("series {}: unknown data type {}", info.node_id,
                                                          static_cast<int>(info.data_type)));
  }
  return {};
}

Error collision(const SeriesInfo& info, const SeriesInfo& existing) {
  return make_error(Errc::state, fmt::format("series id {} of ({}, {}) is already used by ({}, {})",
                                             series_id(info.server, info.node_id), info.server, info.node_id,
                                             existing.server, existing.node_id));
}

Status KnownSeries::check(std::span<const Sample> samples, const Lookup& lookup) {
  for (const auto& s : samples) {
    if (ids_.contains(s.series)) {
      continue;
    }
    auto found = lookup(s.series);
    if (!found) {
      return found.error();
    }
    if (!*found) {
      return make_error(Errc::not_found, fmt::format("series {} is not registered", s.series));
    }
    ids_.insert(s.series);
  }
  return {};
}

}  // namespace sf::historian::detail
