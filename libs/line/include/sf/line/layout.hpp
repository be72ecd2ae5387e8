// Layout: the engineering description of a line — what is where: belts and
// their stations, dispensers, robots and their reach, the machines' PLCs —
// read from a YAML file (the default is layouts/prototype-line.yaml, the
// paper's prototype, §VII Fig. 8). The plant simulates this line; the
// controllers of the real deployment plan their moves and routes from the
// same file, as a real cell's software has its cell's geometry. Every
// key is checked; errors name file:line:column and the key path, and a
// layout that cannot work (a station no robot reaches, belts that do not
// meet, duplicate names, values out of range) is refused before anything
// starts.
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "sf/core/result.hpp"
#include "sf/motion/articulated.hpp"
#include "sf/motion/geometry.hpp"
#include "sf/motion/scara.hpp"

namespace sf::line {

using motion::Vec2;
using motion::Vec3;

struct CandyType {
  std::string where;  // "file:line:column: key path" of its entry, for errors
  std::string name;
  std::string label;
  double unit_weight_g = 0.0;
};

// Slots on a grid: `columns` along the belt, `rows` across it, `pitch`
// apart, centred on the box; slot n is row n / columns, column n % columns.
struct BoxType {
  std::string where;  // "file:line:column: key path" of its entry, for errors
  std::string name;
  std::string label;
  int rows = 1;
  int columns = 1;
  double pitch_m = 0.03;
  Vec3 size_m{0.1, 0.1, 0.05};  // length along the belt, width, height
  double tare_g = 0.0;
  [[nodiscard]] int capacity() const { return rows * columns; }
  // A slot's centre relative to the box centre, in the box's frame (x along the belt).
  [[nodiscard]] Vec2 slot_offset(int slot) const;
};

struct Catalog {
  std::vector<CandyType> candy_types;
  std::vector<BoxType> box_types;
  [[nodiscard]] const CandyType* candy(std::string_view name) const;
  [[nodiscard]] const BoxType* box(std::string_view name) const;
  [[nodiscard]] std::optional<std::size_t> candy_index(std::string_view name) const;
  [[nodiscard]] std::optional<std::size_t> box_index(std::string_view name) const;
};

// The PLC (or robot controller) behind a legacy machine: who made it (for
// the information models) and where it listens (0 = a free port).
struct PlcSpec {
  std::string vendor;
  std::string model;
  std::uint16_t port = 0;
};

struct StationSpec {
  std::string where;  // "file:line:column: key path" of its entry, for errors
  std::string name;
  double at_m = 0.0;  // along its belt
};

struct BeltSpec {
  std::string where;  // "file:line:column: key path" of its entry, for errors
  std::string name;
  std::string label;
  PlcSpec plc;
  std::vector<Vec2> path;  // polyline the belt's surface follows, entry first
  double height_m = 0.8;
  double speed_mps = 0.5;
  double max_speed_mps = 0.8;
  std::vector<std::string> next;  // belts the exit feeds; more than one = a diverter
  std::vector<std::string> capabilities{"conveying"};
  std::vector<StationSpec> stations;
  [[nodiscard]] double length() const;
  // The point `s` metres along the path (clamped to its ends) and the
  // direction of travel there (radians).
  [[nodiscard]] Vec2 point_at(double s) const;
  [[nodiscard]] double heading_at(double s) const;
  [[nodiscard]] const StationSpec* station(std::string_view station_name) const;
};

struct DispenserSpec {
  std::string where;  // "file:line:column: key path" of its entry, for errors
  std::string name;
  std::string candy;
  Vec3 at;  // pick point
  int stock = 0;
  int capacity = 0;
};

enum class RobotKind { smart_scara, legacy_scara, legacy_articulated };
std::string_view to_string(RobotKind kind);

struct RobotSpec {
  std::string where;  // "file:line:column: key path" of its entry, for errors
  std::string name;
  std::string label;
  RobotKind kind = RobotKind::smart_scara;
  std::string vendor;
  std::string model;
  motion::ScaraGeometry scara;              // smart-scara, legacy-scara
  motion::ArticulatedGeometry articulated;  // legacy-articulated
  double tool_speed_mps = 0.5;              // legacy controllers' own moves
  PlcSpec controller;                       // legacy: its controller on Modbus
  std::vector<std::string> stations;        // "belt/station"
  std::vector<std::string> dispensers;
  std::vector<std::string> capabilities{"pick-and-place"};
  // Where the tool waits and passes between dispensers and stations (a SCARA
  // cannot go straight from a dispenser to a slot when the line between them
  // passes too close to its shoulder axis). Default: 15 cm above the first
  // station.
  std::optional<Vec3> home;
  [[nodiscard]] bool reaches(const Vec3& point) const;
  [[nodiscard]] bool legacy() const { return kind != RobotKind::smart_scara; }
};

// Box uploader or downloader: a Mitsubishi-PLC machine at one station.
struct TransferSpec {
  std::string where;  // "file:line:column: key path" of its entry, for errors
  std::string name;
  std::string label;
  PlcSpec plc;
  std::string station;  // "belt/station"
  double cycle_s = 1.5;
  std::vector<std::string> capabilities;  // box-loading (uploader), box-unloading (downloader)
};

// What machines can do: the operations they bid on and the ontology's
// sf:Capability individuals.
inline constexpr std::string_view kCapabilities[] = {"pick-and-place", "box-loading", "box-unloading",
                                                     "conveying", "palletising"};

struct Layout {
  std::string line;
  std::string label;
  Catalog catalog;
  std::vector<BeltSpec> belts;
  std::vector<DispenserSpec> dispensers;
  std::vector<RobotSpec> robots;
  TransferSpec uploader;
  TransferSpec downloader;
  // How close the tool must be to pick (over a dispenser) or place (over a slot).
  double pick_tolerance_m = 0.005;
  double place_tolerance_m = 0.006;
  std::string source;  // file the layout came from

  [[nodiscard]] const BeltSpec* belt(std::string_view name) const;
  [[nodiscard]] std::optional<std::size_t> belt_index(std::string_view name) const;
  [[nodiscard]] const DispenserSpec* dispenser(std::string_view name) const;
  [[nodiscard]] const RobotSpec* robot(std::string_view name) const;
};

// A "belt/station" reference resolved.
struct StationRef {
  std::size_t belt = 0;
  std::size_t station = 0;
  bool operator==(const StationRef&) const = default;
};
Result<StationRef> find_station(const Layout& layout, std::string_view ref);

// Where a candy goes into `slot` of a box of `type` standing in place at a
// station: the slot's centre at the height of the box top.
Vec3 slot_point(const Layout& layout, const StationRef& at, const BoxType& type, int slot);

Result<Layout> load_layout(const std::filesystem::path& file);
Result<Layout> parse_layout(std::string_view yaml, std::string name = "<layout>");
// The shipped default: layouts/prototype-line.yaml, built into the library.
std::string_view default_layout_yaml();
Result<Layout> default_layout();

}  // namespace sf::line
