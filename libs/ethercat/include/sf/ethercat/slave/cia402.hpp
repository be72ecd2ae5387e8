// One CiA 402 drive axis (IEC 61800-7-201 / ETG.6010) in cyclic synchronous
// position mode (0x6060 = 8): the controlword/statusword state machine
// (§6.2: Not ready to switch on → Switch on disabled → Ready to switch on →
// Switched on → Operation enabled, quick stop, fault reaction, fault, fault
// reset) and a motor that follows the target position within velocity and
// acceleration limits, with following-error supervision (0x6065/0x6066).
//
// The axis registers its objects at 0x6000 + 0x800·axis (ETG.6010 §5: the
// object ranges of further axes are offset by 0x800).
#pragma once

#include <cstdint>

#include "sf/ethercat/slave/object_dictionary.hpp"

namespace sf::ethercat::slave {

enum class Cia402State : std::uint8_t {
  NotReadyToSwitchOn,
  SwitchOnDisabled,
  ReadyToSwitchOn,
  SwitchedOn,
  OperationEnabled,
  QuickStopActive,
  FaultReactionActive,
  Fault,
};
const char* to_string(Cia402State s);

inline constexpr std::int8_t kModeCyclicSynchronousPosition = 8;
// Error codes (0x603F, CiA 402 Annex / CiA 301 emergency codes).
inline constexpr std::uint16_t kErrorFollowing = 0x8611;      // following error
inline constexpr std::uint16_t kErrorCommunication = 0x8100;  // fieldbus communication lost

struct AxisDefaults {
  std::uint32_t max_velocity = 1'000'000;              // 0x607F counts/s
  std::uint32_t max_acceleration = 20'000'000;         // 0x60C5 counts/s²
  std::uint32_t quick_stop_deceleration = 50'000'000;  // 0x6085 counts/s²
  std::uint32_t following_error_window = 10'000;       // 0x6065 counts
  std::uint16_t following_error_timeout_ms = 10;       // 0x6066
};

class Cia402Axis {
 public:
  Cia402Axis(ObjectDictionary& od, unsigned axis, AxisDefaults defaults = {});

  [[nodiscard]] std::uint16_t base() const { return base_; }
  [[nodiscard]] std::uint16_t object(std::uint16_t profile_index) const {
    return static_cast<std::uint16_t>(profile_index - 0x6000U + base_);
  }

  // Evaluates the controlword (after new outputs or an SDO write).
  void apply_controlword();
  // Advances the motor by dt seconds and refreshes the input objects.
  void step(double dt);
  // Communication lost (watchdog, OP left while enabled): fault reaction.
  void communication_lost();
  void power_on();

  [[nodiscard]] Cia402State state() const { return state_; }
  [[nodiscard]] double position() const { return position_; }
  [[nodiscard]] double velocity() const { return velocity_; }
  [[nodiscard]] std::uint16_t statusword() const;
  [[nodiscard]] std::uint16_t controlword() const { return controlword_->get<std::uint16_t>(); }
  [[nodiscard]] std::int32_t target_position() const { return target_->get<std::int32_t>(); }
  [[nodiscard]] std::uint16_t error_code() const { return error_code_->get<std::uint16_t>(); }
  [[nodiscard]] double following_error() const { return demand_ - position_; }
  // A fault of the drive itself (overtemperature, encoder, power stage): the
  // fault reaction starts as the drive's own supervision would start it, with
  // `error` in 0x603F (CiA 402 §6.2, transition 13).
  void inject_fault(std::uint16_t error) { fault(error); }
  // Test hook: move the motor (e.g. an external load) without a command.
  void set_position(double counts);

 private:
  void transition(Cia402State to);
  void fault(std::uint16_t error);
  void move(double dt);
  void decelerate(double dt, double deceleration);
  void supervise(double dt);
  void refresh_inputs();

  std::uint16_t base_;
  AxisDefaults defaults_;
  OdEntry* error_code_;
  OdEntry* controlword_;
  OdEntry* statusword_;
  OdEntry* quick_stop_option_;
  OdEntry* mode_;
  OdEntry* mode_display_;
  OdEntry* demand_value_;
  OdEntry* position_actual_;
  OdEntry* following_window_;
  OdEntry* following_timeout_;
  OdEntry* velocity_actual_;
  OdEntry* target_;
  OdEntry* max_velocity_;
  OdEntry* quick_stop_decel_;
  OdEntry* max_accel_;
  OdEntry* following_actual_;

  Cia402State state_ = Cia402State::NotReadyToSwitchOn;
  std::uint16_t last_controlword_ = 0;
  double position_ = 0.0;
  double velocity_ = 0.0;
  double demand_ = 0.0;
  double last_target_ = 0.0;
  double following_time_ = 0.0;  // seconds the following error has been too large
  bool limited_ = false;
};

}  // namespace sf::ethercat::slave
