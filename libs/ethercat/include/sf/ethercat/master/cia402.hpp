// A CiA 402 drive axis (IEC 61800-7-201 / ETG.6010) over the master's process
// image, in cyclic synchronous position mode (CSP, mode 8): the application
// says what it wants (enabled, a target, a trajectory), update() — once per
// cycle, after exchange() — walks the controlword state machine there and
// writes the next target position.
//
// Objects of axis n are at index + 0x800·n (ETG.6010 multi-axis layout):
// controlword 0x6040, statusword 0x6041, modes of operation 0x6060/0x6061,
// target position 0x607A, position actual 0x6064, velocity actual 0x606C.
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <string_view>
#include <vector>

#include "sf/core/result.hpp"
#include "sf/ethercat/master/process_image.hpp"

namespace sf::ethercat::master {

class Master;

namespace cia402 {

// The power drive system states (IEC 61800-7-201 §6.2.3, statusword bits
// 0–3, 5, 6).
enum class State : std::uint8_t {
  NotReadyToSwitchOn,
  SwitchOnDisabled,
  ReadyToSwitchOn,
  SwitchedOn,
  OperationEnabled,
  QuickStopActive,
  FaultReactionActive,
  Fault,
};
std::string_view to_string(State s);
State state_from_statusword(std::uint16_t statusword);

// Controlword commands (IEC 61800-7-201 Table 2).
inline constexpr std::uint16_t kShutdown = 0x0006;
inline constexpr std::uint16_t kSwitchOn = 0x0007;
inline constexpr std::uint16_t kEnableOperation = 0x000F;
inline constexpr std::uint16_t kDisableVoltage = 0x0000;
inline constexpr std::uint16_t kQuickStop = 0x0002;
inline constexpr std::uint16_t kFaultReset = 0x0080;  // on the rising edge of bit 7

// The controlword that moves a drive in `state` one step towards operation
// enabled (enable = true) or switch-on disabled (enable = false).
std::uint16_t next_controlword(State state, bool enable);

inline constexpr std::int8_t kModeCyclicSynchronousPosition = 8;

}  // namespace cia402

class Cia402Axis {
 public:
  // Resolves the axis' PDO entries in the slave's mapping; controlword,
  // statusword, target and actual position must be mapped.
  static Result<Cia402Axis> attach(Master& master, std::size_t position, unsigned axis = 0);

  // Once per cycle, after exchange(): reads the statusword, writes the next
  // controlword and target position.
  void update();

  void enable() { want_enabled_ = true; }
  void disable() { want_enabled_ = false; }
  // Acknowledge a fault (a rising edge of controlword bit 7); enable()
  // afterwards to go back to operation.
  void fault_reset() { fault_reset_requested_ = true; }
  void set_target_position(std::int32_t position);
  // One position per cycle, starting at the next update(); the axis then
  // holds the last one. The positions are copied.
  void follow(std::span<const std::int32_t> trajectory);
  [[nodiscard]] bool trajectory_done() const { return next_point_ >= trajectory_.size(); }

  [[nodiscard]] cia402::State state() const { return cia402::state_from_statusword(statusword()); }
  [[nodiscard]] bool enabled() const { return state() == cia402::State::OperationEnabled; }
  [[nodiscard]] bool fault() const { return state() == cia402::State::Fault; }
  [[nodiscard]] std::uint16_t statusword() const;
  [[nodiscard]] std::uint16_t controlword() const;
  [[nodiscard]] std::int32_t actual_position() const;
  [[nodiscard]] std::int32_t actual_velocity() const;  // 0 if 0x606C is not mapped
  [[nodiscard]] std::int32_t target_position() const { return target_; }
  [[nodiscard]] std::size_t slave_position() const { return position_; }
  [[nodiscard]] unsigned axis() const { return axis_; }

 private:
  Cia402Axis(Master& master, std::size_t position, unsigned axis)
      : master_(&master), position_(position), axis_(axis) {}
  [[nodiscard]] SlaveView view() const;
  std::uint16_t command_for(cia402::State s);

  Master* master_;
  std::size_t position_;
  unsigned axis_;
  EntryRef controlword_;
  EntryRef statusword_;
  EntryRef target_position_;
  EntryRef actual_position_;
  std::optional<EntryRef> actual_velocity_;
  std::optional<EntryRef> mode_;
  bool want_enabled_ = false;
  bool fault_reset_requested_ = false;
  bool fault_reset_edge_ = false;  // bit 7 was low last cycle, set it now
  std::int32_t target_ = 0;
  std::vector<std::int32_t> trajectory_;
  std::size_t next_point_ = 0;
};

}  // namespace sf::ethercat::master
