#include "layout_check.hpp"

#include <algorithm>
#include <deque>
#include <iterator>
#include <set>

#include <fmt/format.h>

namespace sf::line {

namespace {

constexpr double kMeetTolerance = 0.02;  // m: a belt's exit and the next belt's entry
constexpr double kMaxSpeed = 5.0;        // m/s: faster is no conveyor
constexpr int kMaxGrid = 20;             // rows or columns of a box

Error at(const std::string& where, const std::string& message) {
  return make_error(Errc::invalid_argument, fmt::format("{}: {}", where, message));
}

template <typename T>
Status unique_names(const std::vector<T>& items, std::string_view what) {
  std::set<std::string> seen;
  for (const auto& item : items) {
    if (item.name.empty()) {
      return at(item.where, fmt::format("a {} needs a name", what));
    }
    if (!seen.insert(item.name).second) {
      return at(item.where, fmt::format("duplicate {} name '{}'", what, item.name));
    }
  }
  return {};
}

Status check_capabilities(const std::vector<std::string>& capabilities, const std::string& where) {
  for (const auto& c : capabilities) {
    if (std::find(std::begin(kCapabilities), std::end(kCapabilities), c) == std::end(kCapabilities)) {
      return at(where,
                fmt::format("unknown capability '{}' (known: pick-and-place, box-loading, box-unloading, "
                            "conveying, palletising)",
                            c));
    }
  }
  return {};
}

Status check_catalog(const Catalog& c) {
  SF_TRY(unique_names(c.candy_types, "candy type"));
  SF_TRY(unique_names(c.box_types, "box type"));
  for (const auto& t : c.candy_types) {
    if (!(t.unit_weight_g > 0.0 && t.unit_weight_g < 1000.0)) {
      return at(t.where, fmt::format("unit_weight_g {} is not in (0, 1000)", t.unit_weight_g));
    }
  }
  for (const auto& b : c.box_types) {
    if (b.rows < 1 || b.columns < 1 || b.rows > kMaxGrid || b.columns > kMaxGrid) {
      return at(b.where, fmt::format("rows and columns must be 1..{}", kMaxGrid));
    }
    if (!(b.pitch_m > 0.0) || !(b.size_m.x > 0.0 && b.size_m.y > 0.0 && b.size_m.z > 0.0) || b.tare_g < 0.0) {
      return at(b.where, "pitch_m and size_m must be positive, tare_g not negative");
    }
    if ((b.columns - 1) * b.pitch_m >= b.size_m.x || (b.rows - 1) * b.pitch_m >= b.size_m.y) {
      return at(b.where, fmt::format("{}×{} slots {} m apart do not fit in a {}×{} m box", b.columns, b.rows,
                                     b.pitch_m, b.size_m.x, b.size_m.y));
    }
  }
  return {};
}

Status check_belt(const Layout& layout, const BeltSpec& b, double longest_box) {
  if (b.path.size() < 2) {
    return at(b.where, "path needs at least two points");
  }
  for (std::size_t i = 1; i < b.path.size(); ++i) {
    if (motion::norm(b.path[i] - b.path[i - 1]) < 1e-3) {
      return at(b.where, fmt::format("path point {} repeats the one before", i));
    }
  }
  if (b.length() < 2.0 * longest_box) {
    return at(b.where, fmt::format("belt of {:.3f} m is shorter than two boxes", b.length()));
  }
  if (!(b.height_m > 0.0 && b.height_m <= 3.0)) {
    return at(b.where, fmt::format("height_m {} is not in (0, 3]", b.height_m));
  }
  if (!(b.speed_mps > 0.0 && b.speed_mps <= b.max_speed_mps && b.max_speed_mps <= kMaxSpeed)) {
    return at(b.where, fmt::format("speeds must satisfy 0 < speed_mps ({}) <= max_speed_mps ({}) <= {}",
                                   b.speed_mps, b.max_speed_mps, kMaxSpeed));
  }
  for (const auto& name : b.next) {
    const BeltSpec* next = layout.belt(name);
    if (next == nullptr) {
      return at(b.where, fmt::format("next belt '{}' does not exist", name));
    }
    if (next == &b) {
      return at(b.where, "a belt cannot feed itself");
    }
    if (!next->path.empty() && motion::norm(next->path.front() - b.path.back()) > kMeetTolerance) {
      return at(
          b.where,
          fmt::format("belt ends at ({}, {}) but next belt '{}' starts at ({}, {}): they do not connect",
                      b.path.back().x, b.path.back().y, name, next->path.front().x, next->path.front().y));
    }
  }
  SF_TRY(check_capabilities(b.capabilities, b.where));
  SF_TRY(unique_names(b.stations, "station"));
  for (const auto& s : b.stations) {
    if (!(s.at_m >= longest_box / 2.0 && s.at_m <= b.length() - longest_box / 2.0)) {
      return at(s.where, fmt::format("station at {} m does not hold a whole box on a belt of {:.3f} m",
                                     s.at_m, b.length()));
    }
  }
  return {};
}

Status check_robot_station(const Layout& layout, const RobotSpec& r, const std::string& ref) {
  auto s = find_station(layout, ref);
  if (!s) {
    return at(r.where, s.error().message);
  }
  for (const auto& type : layout.catalog.box_types) {
    for (int slot = 0; slot < type.capacity(); ++slot) {
      const Vec3 p = slot_point(layout, *s, type, slot);
      if (!r.reaches(p)) {
        return at(r.where,
                  fmt::format("station {} is out of the robot's reach: slot {} of a {} at ({:.3f}, {:.3f}, "
                              "{:.3f})",
                              ref, slot, type.name, p.x, p.y, p.z));
      }
    }
  }
  return {};
}

Status check_robot(const Layout& layout, const RobotSpec& r) {
  const bool scara = r.kind != RobotKind::legacy_articulated;
  const bool links_ok = scara ? (r.scara.l1 > 0.0 && r.scara.l2 > 0.0 && r.scara.limits[2].max > 0.0)
                              : (r.articulated.shoulder > 0.0 && r.articulated.upper > 0.0 &&
                                 r.articulated.fore > 0.0 && r.articulated.tool > 0.0);
  if (!links_ok) {
    return at(r.where, "links_m and z_stroke_m must be positive");
  }
  if (!(r.tool_speed_mps > 0.0 && r.tool_speed_mps <= kMaxSpeed)) {
    return at(r.where, fmt::format("tool_speed_mps {} is not in (0, {}]", r.tool_speed_mps, kMaxSpeed));
  }
  SF_TRY(check_capabilities(r.capabilities, r.where));
  if (r.stations.empty()) {
    return at(r.where, "a robot needs at least one station");
  }
  for (const auto& ref : r.stations) {
    SF_TRY(check_robot_station(layout, r, ref));
  }
  if (r.home && !r.reaches(*r.home)) {
    return at(r.where, fmt::format("home ({:.3f}, {:.3f}, {:.3f}) is out of the robot's reach", r.home->x,
                                   r.home->y, r.home->z));
  }
  for (const auto& name : r.dispensers) {
    const DispenserSpec* d = layout.dispenser(name);
    if (d == nullptr) {
      return at(r.where, fmt::format("dispenser '{}' does not exist", name));
    }
    if (!r.reaches(d->at)) {
      return at(r.where, fmt::format("dispenser '{}' at ({:.3f}, {:.3f}, {:.3f}) is out of the robot's reach",
                                     name, d->at.x, d->at.y, d->at.z));
    }
  }
  return {};
}

Status check_dispensers(const Layout& layout) {
  SF_TRY(unique_names(layout.dispensers, "dispenser"));
  for (const auto& d : layout.dispensers) {
    if (layout.catalog.candy(d.candy) == nullptr) {
      return at(d.where, fmt::format("candy type '{}' is not in the catalog", d.candy));
    }
    if (d.capacity < 1 || d.capacity > 1'000'000 || d.stock < 0 || d.stock > d.capacity) {
      return at(d.where,
                fmt::format("stock {} and capacity {} must satisfy 0 <= stock <= capacity <= 1000000",
                            d.stock, d.capacity));
    }
  }
  return {};
}

// Every machine is one OPC UA server and one DDS participant: one name each.
Status check_machine_names(const Layout& layout) {
  std::set<std::string> seen;
  auto add = [&](const std::string& name, const std::string& where) -> Status {
    if (!seen.insert(name).second) {
      return at(where, fmt::format("duplicate machine name '{}'", name));
    }
    return {};
  };
  for (const auto& b : layout.belts) {
    SF_TRY(add(b.name, b.where));
  }
  for (const auto& r : layout.robots) {
    SF_TRY(add(r.name, r.where));
  }
  SF_TRY(add(layout.uploader.name, layout.uploader.where));
  return add(layout.downloader.name, layout.downloader.where);
}

Status check_transfer(const Layout& layout, const TransferSpec& t) {
  SF_TRY(check_capabilities(t.capabilities, t.where));
  auto s = find_station(layout, t.station);
  if (!s) {
    return at(t.where, s.error().message);
  }
  if (!(t.cycle_s > 0.0 && t.cycle_s <= 600.0)) {
    return at(t.where, fmt::format("cycle_s {} is not in (0, 600]", t.cycle_s));
  }
  return {};
}

// Every station is where a robot, the uploader or the downloader works.
Status check_stations_served(const Layout& layout) {
  std::set<std::string> served{layout.uploader.station, layout.downloader.station};
  for (const auto& r : layout.robots) {
    served.insert(r.stations.begin(), r.stations.end());
  }
  for (const auto& b : layout.belts) {
    for (const auto& s : b.stations) {
      if (served.count(b.name + "/" + s.name) == 0) {
        return at(s.where,
                  fmt::format("station {}/{} is served by no robot, uploader or downloader", b.name, s.name));
      }
    }
  }
  return {};
}

// A box put on the line at the uploader can reach the downloader.
Status check_route(const Layout& layout) {
  const auto from = find_station(layout, layout.uploader.station);
  const auto to = find_station(layout, layout.downloader.station);
  if (from->belt == to->belt && from->station == to->station) {
    return at(layout.downloader.where, "the downloader works at the uploader's station");
  }
  std::vector<bool> seen(layout.belts.size(), false);
  std::deque<std::size_t> queue{from->belt};
  seen[from->belt] = true;
  while (!queue.empty()) {
    const std::size_t b = queue.front();
    queue.pop_front();
    if (b == to->belt) {
      return {};
    }
    for (const auto& name : layout.belts[b].next) {
      const auto n = layout.belt_index(name);
      if (n && !seen[*n]) {
        seen[*n] = true;
        queue.push_back(*n);
      }
    }
  }
  return at(layout.downloader.where,
            fmt::format("no belt route leads from the uploader ({}) to the downloader ({})",
                        layout.uploader.station, layout.downloader.station));
}

}  // namespace

Status check_layout(const Layout& layout) {
  SF_TRY(check_catalog(layout.catalog));
  double longest = 0.0;
  for (const auto& b : layout.catalog.box_types) {
    longest = std::max(longest, b.size_m.x);
  }
  SF_TRY(unique_names(layout.belts, "belt"));
  if (layout.belts.empty()) {
    return make_error(Errc::invalid_argument, fmt::format("{}: a layout needs belts", layout.source));
  }
  for (const auto& b : layout.belts) {
    SF_TRY(check_belt(layout, b, longest));
  }
  SF_TRY(check_dispensers(layout));
  SF_TRY(unique_names(layout.robots, "robot"));
  for (const auto& r : layout.robots) {
    SF_TRY(check_robot(layout, r));
  }
  SF_TRY(check_machine_names(layout));
  SF_TRY(check_transfer(layout, layout.uploader));
  SF_TRY(check_transfer(layout, layout.downloader));
  SF_TRY(check_stations_served(layout));
  SF_TRY(check_route(layout));
  if (!(layout.pick_tolerance_m > 0.0 && layout.pick_tolerance_m < 0.05 && layout.place_tolerance_m > 0.0 &&
        layout.place_tolerance_m < 0.05)) {
    return make_error(
        Errc::invalid_argument,
        fmt::format("{}: pick_tolerance_m and place_tolerance_m must be in (0, 0.05)", layout.source));
  }
  return {};
}

}  // namespace sf::line
