// PackML (OPC 30050, after ANSI/ISA-TR88.00.02): the state machine every
// machine of the line runs, its commands and unit modes, and the Admin
// counters OEE is computed from. Pure logic on a Clock: the controller says
// when an acting state's work is done (state_complete), the operator or the
// controller gives commands, a fault aborts.
//
//   Stopped ─Reset→ Resetting ─SC→ Idle ─Start→ Starting ─SC→ Execute ─SC→ Completing ─SC→ Complete
//   Execute ─Hold→ Holding ─SC→ Held ─Unhold→ Unholding ─SC→ Execute (Suspend/Unsuspend likewise)
//   any but Aborting/Aborted ─Abort→ Aborting ─SC→ Aborted ─Clear→ Clearing ─SC→ Stopped
//   any but Stopping/Stopped/Aborting/Aborted/Clearing ─Stop→ Stopping ─SC→ Stopped
//   Complete ─Reset→ Resetting
// (SC: state complete.) The numbers are OPC 30050's state and command numbers.
#pragma once

#include <array>
#include <chrono>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

#include "sf/core/clock.hpp"
#include "sf/core/result.hpp"

namespace sf::factory {

enum class PackMLState : std::uint8_t {
  Undefined = 0,
  Clearing = 1,
  Stopped = 2,
  Starting = 3,
  Idle = 4,
  Suspended = 5,
  Execute = 6,
  Stopping = 7,
  Aborting = 8,
  Aborted = 9,
  Holding = 10,
  Held = 11,
  Unholding = 12,
  Suspending = 13,
  Unsuspending = 14,
  Resetting = 15,
  Completing = 16,
  Complete = 17,
};
inline constexpr std::size_t kPackMLStates = 18;
std::string_view to_string(PackMLState state);

enum class PackMLCommand : std::uint8_t {
  Reset = 1,
  Start = 2,
  Stop = 3,
  Hold = 4,
  Unhold = 5,
  Suspend = 6,
  Unsuspend = 7,
  Abort = 8,
  Clear = 9,
};
std::string_view to_string(PackMLCommand command);

enum class PackMLMode : std::uint8_t { Production = 1, Maintenance = 2, Manual = 3 };
std::string_view to_string(PackMLMode mode);

// Why the machine last stopped, held or aborted (PackML Admin.StopReason).
struct StopReason {
  std::int32_t id = 0;
  std::string message;
  Clock::utc_time at{};
};

// The stop reason an operator's Stop, Hold or Abort leaves ("operator: Hold"); nothing for the
// other commands.
inline constexpr std::int32_t kStopOperator = 0;
std::optional<StopReason> operator_stop_reason(PackMLCommand command);

// PackML Admin/Status as a value (for OPC UA and OEE).
struct PackMLStatus {
  PackMLState state = PackMLState::Stopped;
  PackMLMode mode = PackMLMode::Production;
  std::optional<StopReason> stop_reason;
  std::uint64_t produced = 0;                                           // Admin.ProdProcessedCount
  std::uint64_t defective = 0;                                          // Admin.ProdDefectiveCount
  std::array<std::chrono::nanoseconds, kPackMLStates> time_in_state{};  // Admin.StateCumulativeTime
  std::chrono::nanoseconds state_current_time{0};                       // Admin.StateCurrentTime
};

// What a controller does in each state (PackMLUnit::run asks it).
class UnitWork {
 public:
  virtual ~UnitWork() = default;
  virtual void execute() = 0;  // Execute: work on the jobs
  virtual bool reset() = 0;    // Resetting: true once done
  virtual bool clear() = 0;    // Clearing: true once done
  // Holding, Suspending, Stopping: finish the step in progress, start none;
  // true once the machine is settled.
  virtual bool wind_down() = 0;
  virtual void stopped() = 0;  // Stopping is done: drop the jobs
  virtual void abort() = 0;    // Aborting: stop at once, drop everything
  virtual void wait() = 0;     // wait states: follow what still runs, start nothing
};

// The state machine of one unit. Commands that the current state does not
// accept are refused (Errc::state, naming command and state) and change nothing.
class PackMLUnit {
 public:
  explicit PackMLUnit(const Clock& clock, PackMLState initial = PackMLState::Stopped);

  [[nodiscard]] PackMLState state() const { return state_; }
  [[nodiscard]] PackMLMode mode() const { return mode_; }
  // Hold, Stop and Abort may carry why (the stop reason operators see).
  Status command(PackMLCommand command, std::optional<StopReason> why = std::nullopt);
  [[nodiscard]] bool accepts(PackMLCommand command) const;
  // A start without an operator (a controller configured to start by itself), one step per
  // call: Reset in Stopped, Start in Idle. True once in Execute.
  bool advance_to_execute();
  // The acting state's work is done: on to the next state (SC). Refused in a
  // wait state other than Execute (Execute's SC is the end of production).
  Status state_complete();
  // A fault: Abort with the reason (from any state but Aborting/Aborted).
  void fault(StopReason why);
  // Mode changes only where no production runs: Stopped, Idle, Aborted.
  Status set_mode(PackMLMode mode);
  void count(bool good);  // one product processed (defective when not good)
  [[nodiscard]] PackMLStatus status() const;
  // One turn of the controller's work in the current state: its UnitWork is
  // asked what the state needs, acting states complete when it is done.
  void run(UnitWork& work);
  // Acting states: the ones the controller must finish with state_complete().
  [[nodiscard]] static bool acting(PackMLState state);

 private:
  void enter(PackMLState next);

  const Clock* clock_;
  PackMLState state_;
  PackMLMode mode_ = PackMLMode::Production;
  Clock::time_point entered_;
  PackMLStatus totals_;
};

}  // namespace sf::factory
