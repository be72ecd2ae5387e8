// Snapshot: a read-only picture of the plant at one instant — boxes with
// their poses and contents, belts, dispensers, robot tools, the machines'
// faults — for tests, the CLI (`plant --json`) and the dashboard's line view.
#pragma once

#include <chrono>
#include <cstdint>
#include <string>
#include <vector>

#include <nlohmann/json_fwd.hpp>

#include "sf/motion/geometry.hpp"
#include "sf/plant/events.hpp"
#include "sf/plant/world.hpp"

namespace sf::plant {

struct BoxView {
  BoxId id = 0;
  std::string type;
  std::string belt;
  double s = 0.0;
  motion::Vec3 position;
  double heading = 0.0;
  std::string station;             // "belt/station" when in place at one
  std::vector<std::string> slots;  // candy per slot, "" = empty
  bool operator==(const BoxView&) const = default;
};

struct BeltView {
  std::string name;
  bool motor = false;
  bool reverse = false;
  double speed_mps = 0.0;
  std::string exit;  // the belt the diverter feeds, "" = none
  bool jammed = false;
  bool entry_eye = false;
  bool exit_eye = false;
  std::vector<bool> stoppers;
  std::vector<bool> station_eyes;
  bool operator==(const BeltView&) const = default;
};

struct DispenserView {
  std::string name;
  std::string candy;
  int stock = 0;
  bool operator==(const DispenserView&) const = default;
};

struct RobotView {
  std::string name;
  std::string kind;
  motion::ToolPose tool;
  std::vector<double> joints;
  bool gripper = false;
  std::string held;  // candy type in the gripper, "" = none
};

struct MachineView {
  std::string name;
  std::string kind;  // conveyor, uploader, downloader, legacy-robot, smart-robot
  std::uint16_t fault_code = 0;
  std::string fault;  // text of the fault code, or of an injected hardware fault
};

struct Snapshot {
  std::chrono::nanoseconds time{};
  std::vector<BoxView> boxes;
  std::vector<BeltView> belts;
  std::vector<DispenserView> dispensers;
  std::vector<RobotView> robots;
  std::vector<MachineView> machines;
  std::vector<std::string> faults;  // injected and not cleared
  WorldCounters counters;
  std::uint64_t events = 0;  // events so far
};

// The world's part of a snapshot (machines and faults come from the plant).
Snapshot world_snapshot(const World& world);
nlohmann::json to_json(const Snapshot& snapshot);
nlohmann::json to_json(const Event& event);

}  // namespace sf::plant
