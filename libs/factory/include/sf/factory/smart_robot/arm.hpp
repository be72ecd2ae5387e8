// The smart robot's arm as its controller drives it over EtherCAT: our master
// in OP, the arm's four CiA 402 axes in cyclic synchronous position (CSP),
// the vacuum gripper on a DO and its sensors on DIs (line/smart_robot.hpp).
// One cycle() per EtherCAT cycle: exchange, recovery, the next CSP set-point
// of the move in work (motion::CspSampler over a planned path), the drives'
// state machines.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "sf/core/result.hpp"
#include "sf/ethercat/master/cia402.hpp"
#include "sf/ethercat/master/master.hpp"
#include "sf/line/layout.hpp"
#include "sf/line/smart_robot.hpp"
#include "sf/motion/axis_limits.hpp"
#include "sf/motion/cartesian_path.hpp"
#include "sf/motion/csp_sampler.hpp"

namespace sf::factory::smart_robot {

class Arm {
 public:
  Arm(ethercat::master::Master& master, const line::RobotSpec& spec, motion::MotionLimits limits,
      std::size_t slave = 0);

  // Resolves the axes and IO in the slave's mapping (after the segment is in OP).
  Status attach();
  [[nodiscard]] bool attached() const { return !axes_.empty(); }

  // One EtherCAT cycle.
  void cycle();

  // The slave does its part of the cycle (in OP, answering); false from a lost
  // frame or a slave that left OP until the master has brought it back.
  [[nodiscard]] bool link_up() const { return link_up_; }
  [[nodiscard]] const std::string& link_error() const { return link_error_; }

  // Drives: enable from where they stand (the set-point follows the actual
  // position), disable, acknowledge faults.
  void enable();
  void disable();
  void fault_reset();
  [[nodiscard]] bool enabled() const;
  // The first axis in Fault, with its CiA 402 error code (0x603F, read over
  // CoE when the drive faults): "axis 3 (z) fault, error code 0x8611".
  [[nodiscard]] std::optional<std::string> axis_fault();

  // Plans a Cartesian path from the current set-point through `waypoints`.
  [[nodiscard]] Result<motion::CartesianPath> plan(std::span<const motion::Waypoint> waypoints) const;
  [[nodiscard]] Result<motion::CartesianPath> plan_from(const motion::ScaraJoints& start,
                                                        std::span<const motion::Waypoint> waypoints) const;
  // Starts following `path` (planned from the current set-point) at the next cycle.
  void follow(motion::CartesianPath path);
  // Holds the current set-point (the move is abandoned).
  void halt();
  [[nodiscard]] bool moving() const { return sampler_.has_value(); }
  // Not moving and every axis within its in-position window of the set-point.
  [[nodiscard]] bool settled() const;
  // The sampler's error when a move stopped early.
  [[nodiscard]] const std::string& move_error() const { return move_error_; }

  void gripper(bool on) { outputs_ = on ? (outputs_ | line::kDoGripper) : (outputs_ & ~line::kDoGripper); }
  [[nodiscard]] bool gripper_on() const { return (outputs_ & line::kDoGripper) != 0; }
  [[nodiscard]] std::uint32_t inputs() const { return inputs_; }

  [[nodiscard]] const motion::ScaraJoints& setpoint() const { return setpoint_; }
  [[nodiscard]] motion::ScaraJoints actual() const;
  [[nodiscard]] const line::RobotSpec& spec() const { return *spec_; }
  [[nodiscard]] const motion::MotionLimits& limits() const { return limits_; }
  [[nodiscard]] std::span<const ethercat::master::Cia402Axis> axes() const { return axes_; }
  [[nodiscard]] std::uint32_t serial_number() const;

 private:
  void update_link(const ethercat::master::ExchangeResult& result);
  void sample();
  void write_setpoint();
  [[nodiscard]] std::string drive_not_enabled() const;

  ethercat::master::Master* master_;
  const line::RobotSpec* spec_;
  motion::MotionLimits limits_;
  std::size_t slave_;
  std::vector<ethercat::master::Cia402Axis> axes_;
  ethercat::master::EntryRef do_;
  ethercat::master::EntryRef di_;
  std::uint32_t outputs_ = 0;
  std::uint32_t inputs_ = 0;
  bool link_up_ = false;
  bool slave_down_ = false;  // the master reported it lost or out of state, not yet recovered
  unsigned failed_cycles_ = 0;
  std::string link_error_ = "not started";
  motion::ScaraJoints setpoint_{};
  std::optional<motion::CartesianPath> path_;
  std::optional<motion::CspSampler> sampler_;
  std::string move_error_;
  std::array<std::optional<std::uint16_t>, line::kArmAxes> error_codes_{};
};

}  // namespace sf::factory::smart_robot
