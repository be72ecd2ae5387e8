// A "load" operation of the smart robot as the arm performs it: for each
// candy, a pick path to the dispenser, the vacuum on until the cup holds a
// part, a place path over the robot's home point into the slot, the vacuum
// off until the part is gone, and a retract. Way-points between the stops
// are blended, so the tool passes them without stopping.
#pragma once

#include <chrono>
#include <cstdint>
#include <string>
#include <vector>

#include "sf/core/result.hpp"
#include "sf/factory/machine.hpp"
#include "sf/factory/smart_robot.hpp"
#include "sf/line/layout.hpp"
#include "sf/motion/axis_limits.hpp"
#include "sf/motion/cartesian_path.hpp"

namespace sf::factory::smart_robot {

// A checked load: everything the arm needs, resolved from the operation's parameters.
struct LoadJob {
  std::size_t candy = 0;
  std::string candy_name;
  const line::DispenserSpec* dispenser = nullptr;
  const line::BoxType* box_type = nullptr;
  int first_slot = 0;
  int count = 1;
  std::uint32_t box = 0;
  line::StationRef station;
  std::size_t station_index = 0;  // among the robot's stations: its box-in-place DI
};

// The parameters checked against the layout and the robot: a candy it has a
// dispenser for, slots within the box type's capacity, a station of its own
// (the "station" parameter, an index among its stations, default 0).
Result<LoadJob> resolve_load(const line::Layout& layout, const line::RobotSpec& robot, const Operation& op);

// The robot's home: where the tool passes between dispensers and stations
// (the layout's, else 15 cm above its first station).
motion::Vec3 home_point(const line::Layout& layout, const line::RobotSpec& robot);

// One leg of the sequence.
struct Leg {
  enum class Kind : std::uint8_t { move, grip, release };
  Kind kind = Kind::move;
  std::vector<motion::Waypoint> waypoints;  // move: from wherever the arm is
  int candy = 0;                            // which of the job's candies (0-based)
};

// The legs of the whole job, in order.
std::vector<Leg> load_legs(const line::Layout& layout, const line::RobotSpec& robot, const LoadJob& job,
                           const PickPlace& how);

// What the job would take from joints `start`: the planned paths' durations
// plus the grip and release times. Errors name the leg that cannot be planned.
Result<std::chrono::nanoseconds> load_duration(const line::RobotSpec& robot,
                                               const motion::MotionLimits& limits,
                                               const motion::ScaraJoints& start, const std::vector<Leg>& legs,
                                               const PickPlace& how);

// The way-points of a move without those the tool is already at (a zero-length line cannot be planned).
std::vector<motion::Waypoint> from_here(const motion::Vec3& here,
                                        const std::vector<motion::Waypoint>& waypoints);

}  // namespace sf::factory::smart_robot
