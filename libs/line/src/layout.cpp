// Layout queries: names, belt geometry, slot positions, reach.
#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "sf/line/layout.hpp"

namespace sf::line {

namespace {

template <typename T>
const T* by_name(const std::vector<T>& items, std::string_view name) {
  auto it = std::find_if(items.begin(), items.end(), [&](const T& t) { return t.name == name; });
  return it == items.end() ? nullptr : &*it;
}

template <typename T>
std::optional<std::size_t> index_of(const std::vector<T>& items, std::string_view name) {
  auto it = std::find_if(items.begin(), items.end(), [&](const T& t) { return t.name == name; });
  if (it == items.end()) {
    return std::nullopt;
  }
  return static_cast<std::size_t>(it - items.begin());
}

}  // namespace

Vec2 BoxType::slot_offset(int slot) const {
  const int row = slot / columns;
  const int column = slot % columns;
  return {(column - (columns - 1) / 2.0) * pitch_m, (row - (rows - 1) / 2.0) * pitch_m};
}

const CandyType* Catalog::candy(std::string_view name) const {
  return by_name(candy_types, name);
}
const BoxType* Catalog::box(std::string_view name) const {
  return by_name(box_types, name);
}
std::optional<std::size_t> Catalog::candy_index(std::string_view name) const {
  return index_of(candy_types, name);
}
std::optional<std::size_t> Catalog::box_index(std::string_view name) const {
  return index_of(box_types, name);
}

double BeltSpec::length() const {
  double sum = 0.0;
  for (std::size_t i = 1; i < path.size(); ++i) {
    sum += motion::norm(path[i] - path[i - 1]);
  }
  return sum;
}

Vec2 BeltSpec::point_at(double s) const {
  if (path.empty()) {
    return {};
  }
  for (std::size_t i = 1; i < path.size(); ++i) {
    const double leg = motion::norm(path[i] - path[i - 1]);
    if (s <= leg || i + 1 == path.size()) {
      const double t = leg > 0.0 ? std::clamp(s / leg, 0.0, 1.0) : 0.0;
      return path[i - 1] + t * (path[i] - path[i - 1]);
    }
    s -= leg;
  }
  return path.front();
}

double BeltSpec::heading_at(double s) const {
  for (std::size_t i = 1; i < path.size(); ++i) {
    const double leg = motion::norm(path[i] - path[i - 1]);
    if (s < leg || i + 1 == path.size()) {
      const Vec2 d = path[i] - path[i - 1];
      return std::atan2(d.y, d.x);
    }
    s -= leg;
  }
  return 0.0;
}

const StationSpec* BeltSpec::station(std::string_view station_name) const {
  return by_name(stations, station_name);
}

std::string_view to_string(RobotKind kind) {
  switch (kind) {
    case RobotKind::smart_scara:
      return "smart-scara";
    case RobotKind::legacy_scara:
      return "legacy-scara";
    case RobotKind::legacy_articulated:
      return "legacy-articulated";
  }
  return "?";
}

bool RobotSpec::reaches(const Vec3& point) const {
  if (kind == RobotKind::legacy_articulated) {
    return motion::articulated_reaches(articulated, point);
  }
  return motion::scara_reaches(scara, point);
}

const BeltSpec* Layout::belt(std::string_view name) const {
  return by_name(belts, name);
}
std::optional<std::size_t> Layout::belt_index(std::string_view name) const {
  return index_of(belts, name);
}
const DispenserSpec* Layout::dispenser(std::string_view name) const {
  return by_name(dispensers, name);
}
const RobotSpec* Layout::robot(std::string_view name) const {
  return by_name(robots, name);
}

Result<StationRef> find_station(const Layout& layout, std::string_view ref) {
  const auto slash = ref.find('/');
  if (slash == std::string_view::npos) {
    return make_error(Errc::invalid_argument,
                      fmt::format("station '{}' is not of the form belt/station", ref));
  }
  const auto belt = layout.belt_index(ref.substr(0, slash));
  if (!belt) {
    return make_error(Errc::not_found, fmt::format("station '{}': no belt '{}'", ref, ref.substr(0, slash)));
  }
  const auto& stations = layout.belts[*belt].stations;
  const auto station = index_of(stations, ref.substr(slash + 1));
  if (!station) {
    return make_error(Errc::not_found, fmt::format("station '{}': belt '{}' has no station '{}'", ref,
                                                   ref.substr(0, slash), ref.substr(slash + 1)));
  }
  return StationRef{*belt, *station};
}

Vec3 slot_point(const Layout& layout, const StationRef& at, const BoxType& type, int slot) {
  const BeltSpec& belt = layout.belts.at(at.belt);
  const double s = belt.stations.at(at.station).at_m;
  const Vec2 p = belt.point_at(s) + motion::rotate(type.slot_offset(slot), belt.heading_at(s));
  return {p.x, p.y, belt.height_m + type.size_m.z};
}

}  // namespace sf::line
