// Places and conveyor segments (conveying.hpp).
#include "sf/factory/conveying.hpp"

#include <algorithm>
#include <cmath>

namespace sf::factory {

std::vector<Place> places(const line::Layout& layout) {
  std::vector<Place> out;
  for (std::size_t b = 0; b < layout.belts.size(); ++b) {
    const line::BeltSpec& belt = layout.belts[b];
    out.push_back({belt.name, b, std::nullopt, 0.0});
    for (std::size_t k = 0; k < belt.stations.size(); ++k) {
      out.push_back({belt.name + "/" + belt.stations[k].name, b, k, belt.stations[k].at_m});
    }
  }
  return out;
}

std::optional<std::size_t> place_index(const line::Layout& layout, std::string_view name) {
  const auto all = places(layout);
  auto it = std::find_if(all.begin(), all.end(), [&](const Place& p) { return p.name == name; });
  if (it == all.end()) {
    return std::nullopt;
  }
  return static_cast<std::size_t>(it - all.begin());
}

std::optional<double> belt_travel(const line::Layout& layout, std::size_t belt, const Place& from,
                                  const Place& to) {
  const line::BeltSpec& spec = layout.belts.at(belt);
  if (from.belt != belt) {
    return std::nullopt;
  }
  if (to.belt == belt) {
    if (!to.station || to.at_m <= from.at_m) {
      return std::nullopt;
    }
    return to.at_m - from.at_m;
  }
  const bool fed =
      std::find(spec.next.begin(), spec.next.end(), layout.belts.at(to.belt).name) != spec.next.end();
  if (!fed || to.station) {
    return std::nullopt;
  }
  return spec.length() - from.at_m;
}

std::vector<TransportSegment> conveyor_segments(const line::Layout& layout, std::size_t belt) {
  const line::BeltSpec& spec = layout.belts.at(belt);
  std::vector<Place> mine;
  std::vector<Place> next;
  for (auto& p : places(layout)) {
    if (p.belt == belt) {
      mine.push_back(std::move(p));
    } else if (!p.station &&
               std::find(spec.next.begin(), spec.next.end(), layout.belts[p.belt].name) != spec.next.end()) {
      next.push_back(std::move(p));
    }
  }
  std::vector<TransportSegment> out;
  auto add = [&](const Place& from, const Place& to) {
    if (auto metres = belt_travel(layout, belt, from, to)) {
      out.push_back({from.name, to.name, *metres, travel_time(*metres, spec.speed_mps)});
    }
  };
  for (std::size_t i = 0; i + 1 < mine.size(); ++i) {
    add(mine[i], mine[i + 1]);
  }
  for (const Place& to : next) {
    add(mine.back(), to);
  }
  return out;
}

std::chrono::nanoseconds travel_time(double metres, double speed_mps) {
  if (speed_mps <= 0.0) {
    return std::chrono::nanoseconds::max();
  }
  return std::chrono::nanoseconds(std::llround(metres / speed_mps * 1e9));
}

}  // namespace sf::factory
