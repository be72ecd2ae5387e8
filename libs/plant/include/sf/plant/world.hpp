// World: the physical line the plant simulates — boxes on conveyor belts,
// stoppers and photo-eyes at stations, candy dispensers, the tools of the
// robots, the downloader's inspection (scale and vision count). Pure physics
// in fixed steps of simulated time; it knows nothing of EtherCAT or Modbus.
// The machines' own controllers (PLC programs, the smart robot's drives) act
// on it through this API, as motors, grippers and sensors act on a real line.
//
// Single-threaded: the owner serialises calls (the plant holds one mutex).
#pragma once

#include <chrono>
#include <cstdint>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include "sf/core/result.hpp"
#include "sf/line/layout.hpp"
#include "sf/line/registers.hpp"
#include "sf/motion/geometry.hpp"
#include "sf/plant/events.hpp"

namespace sf::plant {

// The plant is built on the line's description: its layout, catalog and
// register maps are the plant's vocabulary.
using namespace sf::line;  // NOLINT(google-build-using-namespace)

inline constexpr std::chrono::nanoseconds kWorldStep = std::chrono::milliseconds{1};
inline constexpr double kEyeInset = 0.05;           // m: entry and exit photo-eyes from the belt's ends
inline constexpr double kInPlaceTolerance = 0.002;  // m: a box this close to a station is in place

struct Box {
  BoxId id = 0;
  std::size_t type = 0;    // catalog box type
  std::vector<int> slots;  // catalog candy type per slot, −1 = empty
  std::size_t belt = 0;
  double s = 0.0;  // metres along the belt (box centre)
  std::uint64_t moved_step = 0;
  int station = -1;  // the station of its belt it stands in place at, −1 = none
};

struct BeltState {
  bool motor = false;
  bool reverse = false;
  double speed_mps = 0.0;
  std::size_t exit = 0;        // index into the layout's `next` (the diverter)
  std::vector<bool> stoppers;  // per station: up = holds an arriving box
  bool jammed = false;         // fault: the belt slips, boxes stand, the exit eye is stuck
  double odometer_m = 0.0;     // belt travel since start
};

// The air around the line, °C: where the robots' drives cool down to.
inline constexpr double kAmbientTemperatureC = 25.0;

struct Tool {
  motion::ToolPose pose;
  bool gripper = false;        // closed (vacuum on)
  int held = -1;               // catalog candy type, −1 = none
  std::vector<double> joints;  // for observation
  // The arm's drives: the hottest winding, °C, and whether their cooling has failed (the fault
  // overheat:ROBOT).
  double drive_temperature_c = kAmbientTemperatureC;
  bool cooling_failed = false;
};

struct Inspection {
  BoxId box = 0;
  std::size_t type = 0;
  double weight_g = 0.0;
  std::vector<int> counts;  // per catalog candy type
};

struct WorldCounters {
  std::uint64_t uploaded = 0;
  std::uint64_t downloaded = 0;
  std::uint64_t picked = 0;
  std::uint64_t placed = 0;
  std::uint64_t dropped = 0;
  std::uint64_t pick_missed = 0;
  std::uint64_t boxes_lost = 0;
};

class World {
 public:
  explicit World(Layout layout, std::uint64_t seed = 1);

  [[nodiscard]] const Layout& layout() const { return layout_; }
  [[nodiscard]] std::chrono::nanoseconds time() const { return time_; }
  // Moves the world forward in fixed steps (the remainder is kept).
  void advance(std::chrono::nanoseconds dt);
  [[nodiscard]] std::mt19937_64& random() { return rng_; }

  // --- conveyor belts (a conveyor PLC's outputs and inputs) ---
  [[nodiscard]] const BeltState& belt(std::size_t b) const { return belts_.at(b); }
  void set_motor(std::size_t b, bool on, bool reverse);
  void set_speed(std::size_t b, double mps);  // clamped to [0, max_speed]
  void set_exit(std::size_t b, std::size_t next_index);
  void set_stopper(std::size_t b, std::size_t station, bool up);
  void set_jam(std::size_t b, bool jammed);
  [[nodiscard]] bool entry_eye(std::size_t b) const;
  [[nodiscard]] bool exit_eye(std::size_t b) const;
  [[nodiscard]] bool station_eye(std::size_t b, std::size_t station) const;
  // The box standing at a station (centre within kInPlaceTolerance), if any.
  [[nodiscard]] const Box* box_in_place(std::size_t b, std::size_t station) const;
  // The station's tag reader (RFID on the box carrier): the id of the box
  // standing at rest in place there, 0 when none. The reader reads when the
  // station's in-position check sees a carrier at rest, so a box passing
  // through on a running belt is not read.
  [[nodiscard]] std::uint16_t tag_reading(std::size_t b, std::size_t station) const;

  // --- boxes ---
  // A new empty box at a station (the uploader's), if the place is free.
  Result<BoxId> place_box(std::size_t type, const StationRef& at, std::string_view by);
  // Takes the box in place at a station off the line and inspects it.
  Result<Inspection> take_box(const StationRef& at, std::string_view by);
  // Fault: a box falls off the line.
  Status drop_box(BoxId id);
  [[nodiscard]] const Box* box(BoxId id) const;
  [[nodiscard]] const std::vector<Box>& boxes() const { return boxes_; }  // on the line, oldest first
  [[nodiscard]] motion::Vec3 box_position(const Box& box) const;
  [[nodiscard]] double box_heading(const Box& box) const;
  [[nodiscard]] motion::Vec3 slot_position(const Box& box, int slot) const;

  // --- dispensers ---
  [[nodiscard]] int stock(std::size_t dispenser) const { return stock_.at(dispenser); }
  void set_stock(std::size_t dispenser, int stock);
  // Fault: the dispenser was refilled with the wrong candy, the catalog's
  // next type (wrapping); a pick there takes that one until it is restored.
  void set_mixup(std::size_t dispenser, bool mixed_up);
  [[nodiscard]] bool mixed_up(std::size_t dispenser) const { return mixed_up_.at(dispenser); }
  // The catalog candy type a pick at the dispenser takes now.
  [[nodiscard]] std::size_t dispensed_candy(std::size_t dispenser) const;

  // --- robot tools: pose and gripper as the arm and its valve make them ---
  [[nodiscard]] const Tool& tool(std::size_t robot) const { return tools_.at(robot); }
  void set_tool(std::size_t robot, const motion::ToolPose& pose, std::vector<double> joints = {});
  // Closing over a dispenser picks a candy; opening over a box slot places
  // it; opening anywhere else drops it.
  void set_gripper(std::size_t robot, bool closed);
  // The drives over `dt` seconds, moving the arm or not (a first-order thermal model).
  void heat_drives(std::size_t robot, double dt, bool moving);
  void set_cooling_failed(std::size_t robot, bool failed);

  // --- observation ---
  [[nodiscard]] const EventLog& events() const { return events_; }
  [[nodiscard]] const WorldCounters& counters() const { return counters_; }
  void record(EventKind kind, std::string where, BoxId box = 0, int slot = -1, std::string candy = {},
              std::string detail = {});

 private:
  void step();
  void move_belt(std::size_t b, double dt);
  void move_forward(std::size_t b, Box& box, double ds, const Box* ahead);
  void move_backward(std::size_t b, Box& box, double ds, const Box* behind);
  void note_station(Box& box, bool moved);
  // The belt a box at the end of belt b crosses onto (the diverter's choice), if any.
  [[nodiscard]] std::optional<std::size_t> exit_of(std::size_t b) const;
  // True while the box is partly on the next belt (its front past the end).
  [[nodiscard]] bool crossing(const Box& box) const;
  // Nothing on belt b, nor crossing onto it, reaches below `front`; or, for
  // a place in the middle, nothing overlaps [s − half, s + half].
  [[nodiscard]] bool entry_free(std::size_t b, double front, BoxId except) const;
  [[nodiscard]] bool span_free(std::size_t b, double s, double half, BoxId except) const;
  [[nodiscard]] bool covered(std::size_t b, double s) const;
  // False as soon as `hit` is true for a box on belt b near [lo, hi] or at
  // the front of a belt feeding it.
  template <typename F>
  [[nodiscard]] bool none_near(std::size_t b, double lo, double hi, F hit) const;
  // on_belt_ from scratch: after each step and whenever boxes come or go.
  void reindex();
  [[nodiscard]] double box_length(const Box& box) const;
  void pick(std::size_t robot);
  void release(std::size_t robot);
  [[nodiscard]] std::string station_name(std::size_t b, std::size_t station) const;

  Layout layout_;
  std::mt19937_64 rng_;
  std::chrono::nanoseconds time_{0};
  std::chrono::nanoseconds pending_{0};
  std::uint64_t steps_ = 0;
  std::vector<BeltState> belts_;
  std::vector<Box> boxes_;
  std::vector<std::vector<std::size_t>> on_belt_;  // indexes into boxes_, per belt
  std::vector<std::vector<std::size_t>> feeders_;  // belts whose `next` includes the belt
  std::vector<std::vector<std::size_t>> next_;     // the layout's `next` as belt indexes
  std::vector<double> length_;                     // of each belt's path
  double max_half_ = 0.0;                          // half the longest box type
  std::vector<Box*> moving_;                       // move_belt's scratch list
  std::vector<int> stock_;
  std::vector<bool> mixed_up_;  // per dispenser
  std::vector<Tool> tools_;
  BoxId next_box_ = 1;
  EventLog events_;
  WorldCounters counters_;
};

}  // namespace sf::plant
