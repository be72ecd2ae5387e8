// The hardware of a smart robot (paper §VII.A): a SCARA arm whose joints are
// driven by the smart controller's ET1100 slave on its own EtherCAT segment.
// The plant couples the slave to the world as sf/line/smart_robot.hpp lays
// down: axis positions are the arm's joints, DO 0 works the vacuum gripper,
// the DIs report what the cell's sensors see.
#pragma once

#include <cstdint>
#include <memory>

#include "sf/core/clock.hpp"
#include "sf/ethercat/slave/devices.hpp"
#include "sf/ethercat/slave/segment.hpp"
#include "sf/line/smart_robot.hpp"
#include "sf/motion/scara.hpp"
#include "sf/plant/world.hpp"

namespace sf::plant {

class SmartRobotCell {
 public:
  // The segment runs on `clock` (the plant's); the arm starts parked with
  // the tool raised over its first station.
  SmartRobotCell(World& world, std::size_t robot, const Clock& clock, std::uint32_t serial);

  [[nodiscard]] const std::string& name() const { return name_; }
  [[nodiscard]] ethercat::slave::Segment& segment() { return *segment_; }
  [[nodiscard]] ethercat::slave::SmartController& controller();
  // Reads the arm from the drives and the gripper from DO 0, writes the DIs.
  // Takes the segment's lock (order: world, then segment).
  void scan(World& world);

  // Faults at the hardware face.
  void axis_fault(unsigned axis, std::uint16_t error_code);
  void cut_cable();      // the slave drops out of the ring: frames come back unanswered
  void restore_cable();  // power and link come back: the slave restarts in INIT
  [[nodiscard]] bool cable_cut() const { return cable_cut_; }

 private:
  std::size_t robot_;
  std::string name_;
  std::unique_ptr<ethercat::slave::Segment> segment_;
  bool cable_cut_ = false;
};

}  // namespace sf::plant
