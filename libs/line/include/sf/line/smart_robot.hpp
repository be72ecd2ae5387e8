// The documented interface of a smart robot's EtherCAT slave (paper §VII.A):
// which axis of the smart controller (8 CiA 402 axes, 32 DI, 32 DO) drives
// which joint of the SCARA arm and at what scale, and what the digital
// inputs and outputs mean. The plant's arm and the machine's controller
// both follow it.
//
//   axis 0  θ1 shoulder   kCountsPerRadian counts/rad
//   axis 1  θ2 elbow      kCountsPerRadian counts/rad
//   axis 2  z             kCountsPerMetre counts/m, 0 = the z axis' bottom
//   axis 3  θ4 wrist      kCountsPerRadian counts/rad
//   axes 4–7              present, not connected to the arm
//   DO 0    vacuum gripper on
//   DI 0    part present (a candy on the cup)
//   DI 1    vacuum ok (gripper on and holding)
//   DI 2+k  box in place at the robot's station k (k < 14)
//   DI 16–31 the tag reader of the robot's first station, wired in parallel:
//           the id of the box in place there (bit 16 = LSB), 0 = none
#pragma once

#include <array>
#include <cstdint>

#include "sf/motion/scara.hpp"

namespace sf::line {

inline constexpr double kCountsPerRadian = 100'000.0;
inline constexpr double kCountsPerMetre = 1'000'000.0;
inline constexpr std::uint32_t kDoGripper = 1U << 0;
inline constexpr std::uint32_t kDiPartPresent = 1U << 0;
inline constexpr std::uint32_t kDiVacuumOk = 1U << 1;
inline constexpr unsigned kDiBoxInPlace = 2;  // + station
// The first station's tag reader (RFID on the box carrier): which box stands
// there, so the controller begins the job of that box and no other.
inline constexpr unsigned kDiBoxId = 16;
inline constexpr unsigned kDiBoxIdBits = 16;
constexpr std::uint16_t box_id_of(std::uint32_t inputs) {
  return static_cast<std::uint16_t>(inputs >> kDiBoxId);
}
inline constexpr unsigned kArmAxes = 4;
// The arm's linear axis (z, metres); the others turn (radians).
inline constexpr unsigned kZAxis = 2;

// Joint values of the arm ↔ axis positions in counts.
motion::ScaraJoints joints_from_counts(const std::array<double, kArmAxes>& counts);
std::array<std::int32_t, kArmAxes> counts_from_joints(const motion::ScaraJoints& joints);

}  // namespace sf::line
