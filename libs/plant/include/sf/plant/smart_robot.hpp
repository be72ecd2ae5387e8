// The hardware of a smart robot (paper §VII.A): a SCARA arm whose joints are
// driven by the smart controller's ET1100 slave (8 CiA 402 axes, 32 DI,
// 32 DO) on its own EtherCAT segment. The plant couples the slave to the
// world: axis positions are the arm's joints, a digital output works the
// vacuum gripper, digital inputs report what the cell's sensors see.
//
//   axis 0  θ1 shoulder   kCountsPerRadian counts/rad
//   axis 1  θ2 elbow      kCountsPerRadian counts/rad
//   axis 2  z             kCountsPerMetre counts/m, 0 = the z axis' bottom
//   axis 3  θ4 wrist      kCountsPerRadian counts/rad
//   axes 4–7              present, not connected to the arm
//   DO 0    vacuum gripper on
//   DI 0    part present (a candy on the cup)
//   DI 1    vacuum ok (gripper on and holding)
//   DI 2+k  box in place at the robot's station k
#pragma once

#include <cstdint>
#include <memory>

#include "sf/core/clock.hpp"
#include "sf/ethercat/slave/devices.hpp"
#include "sf/ethercat/slave/segment.hpp"
#include "sf/motion/scara.hpp"
#include "sf/plant/world.hpp"

namespace sf::plant {

inline constexpr double kCountsPerRadian = 100'000.0;
inline constexpr double kCountsPerMetre = 1'000'000.0;
inline constexpr std::uint32_t kDoGripper = 1U << 0;
inline constexpr std::uint32_t kDiPartPresent = 1U << 0;
inline constexpr std::uint32_t kDiVacuumOk = 1U << 1;
inline constexpr unsigned kDiBoxInPlace = 2;  // + station
inline constexpr unsigned kArmAxes = 4;

// Joint values of the arm ↔ axis positions in counts.
motion::ScaraJoints joints_from_counts(const std::array<double, kArmAxes>& counts);
std::array<std::int32_t, kArmAxes> counts_from_joints(const motion::ScaraJoints& joints);

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
