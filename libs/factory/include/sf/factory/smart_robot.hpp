// The smart robot's controller (paper §VII.A): the IPC of SCARA Robot 1,
// which hosts the EtherCAT master of the robot's own segment and turns awarded
// "load" operations into CSP set-points for the arm's servo axes, one per
// EtherCAT cycle (1 kHz), from the motion planner's blended Cartesian paths.
//
// A load (machine.hpp) begins once its box stands at the robot's station:
// the first station's tag reader (DI 16–31) reads the job's box on two
// consecutive cycles (another station: its box-in-place DI 2+k). The first
// queued job whose box is there begins, so a box that arrives early is served
// while an earlier job's box is still on its way. Then per candy: over the home point to the dispenser,
// vacuum on until part-present and vacuum-ok, over home into the slot, vacuum off until the part is gone,
// retract; home at the end.
//
// PackML (OPC 30050): Stopped ─Reset→ Resetting (fault reset, drives enabled,
// homing) → Idle ─Start→ Execute; jobs run only in Execute. Hold and Suspend
// finish the move in progress and then wait; Stop does too, then drops the
// jobs; Abort stops the axes at once and drops everything.
// Faults:
//   - an axis in Fault (CiA 402 statusword bit 3; error code 0x603F read over
//     CoE) aborts the unit, stop reason kStopAxisFault; the job in work fails.
//     Clear resets the drive faults, Reset enables and homes again.
//   - the segment lost (frames do not come back, the slave leaves OP) stops
//     the unit (kStopEtherCatLost; the outputs are off in the slave's safe
//     state); once the master has brought the slave back to OP the
//     controller resets by itself and is Idle again.
//   - no part on the cup after a pick: the dispenser counts as empty, the job
//     fails and the robot makes no estimates for that candy until a Reset.
//   - a part that does not leave the cup aborts the unit (kStopPartStuck).
// Admin counters: every job that came into work is produced, failed ones defective.
#pragma once

#include <chrono>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "sf/core/clock.hpp"
#include "sf/ethercat/master/master.hpp"
#include "sf/factory/job_queue.hpp"
#include "sf/factory/machine.hpp"
#include "sf/factory/packml.hpp"
#include "sf/line/layout.hpp"
#include "sf/motion/axis_limits.hpp"

namespace sf::factory {

namespace smart_robot {
class Arm;
struct Leg;
struct LoadJob;
}  // namespace smart_robot

inline constexpr std::int32_t kStopAxisFault = 201;
inline constexpr std::int32_t kStopEtherCatLost = 202;
inline constexpr std::int32_t kStopPartStuck = 203;
inline constexpr std::int32_t kStopHomingFailed = 204;

// How the robot picks and places.
struct PickPlace {
  double approach_m = 0.05;  // above a dispenser or slot before going straight down
  double release_m = 0.01;   // above the slot's top where the vacuum lets go
  double blend_m = 0.02;     // blend radius at the passing way-points
  // Waits for the gripper's sensors: longer means the dispenser is empty (no
  // part on the cup) or the part sticks to it.
  std::chrono::milliseconds grip_timeout{300};
  std::chrono::milliseconds release_timeout{300};
  // What a grip and a release take, for the estimates.
  std::chrono::milliseconds grip_time{30};
  std::chrono::milliseconds release_time{30};
};

struct SmartRobotConfig {
  std::string robot;          // its name in the layout
  std::string serial_number;  // empty: the smart controller's SII serial number
  std::size_t slave = 0;      // the smart controller's position in the segment
  motion::MotionLimits limits;
  PickPlace pick_place;
  // Reset and Start by itself at start-up (and Start again after a reconnect).
  bool auto_start = false;
  // A job still running this long after its estimate fails.
  std::chrono::milliseconds job_timeout{std::chrono::seconds{10}};
};

class SmartRobot final : public MachineController, private UnitWork {
 public:
  // The master drives the robot's segment and must outlive the controller.
  SmartRobot(SmartRobotConfig config, line::Layout layout, ethercat::master::Master& master,
             const Clock& clock);
  ~SmartRobot() override;
  SmartRobot(const SmartRobot&) = delete;
  SmartRobot& operator=(const SmartRobot&) = delete;

  // Brings the segment up to OP and attaches the arm's axes and IO. Errors:
  // the robot is not a smart robot of the layout, the segment does not come
  // up, the slave does not map the smart controller's objects.
  Status start();

  [[nodiscard]] const Identification& identification() const override { return identification_; }
  [[nodiscard]] std::vector<std::string> operations() const override;
  [[nodiscard]] std::optional<Estimate> estimate(const Operation& op,
                                                 std::string* why_not = nullptr) const override;
  Status submit(const std::string& job, const Operation& op) override;
  Status cancel(const std::string& job) override;
  Status command(PackMLCommand command) override;
  // One EtherCAT cycle and the controller's work in it; next call one cycle later.
  Clock::time_point poll(Clock::time_point now) override;
  [[nodiscard]] ControllerStatus status() const override;
  [[nodiscard]] bool working() const override { return jobs_.current() != nullptr; }

  [[nodiscard]] const line::Layout& layout() const { return layout_; }
  [[nodiscard]] const smart_robot::Arm& arm() const { return *arm_; }
  // The candy types whose dispenser ran empty (catalog indexes), until a Reset.
  [[nodiscard]] const std::set<std::size_t>& empty_dispensers() const { return empty_; }

 private:
  enum class ResetStep : std::uint8_t { enable, home, done };

  [[nodiscard]] std::optional<std::string> refusal(const Operation& op) const;
  void watch_faults();
  void watch_link();
  void auto_start();
  // UnitWork: the robot's part in each PackML state.
  void execute() override;
  bool reset() override;
  bool clear() override;
  bool wind_down() override;
  void stopped() override;
  void abort() override;
  void wait() override;
  void work(bool go);
  bool begin_job();
  // The tag reader's reading, kept when two consecutive cycles agree.
  void read_tag();
  [[nodiscard]] bool box_ready(const Operation& op) const;
  void begin_leg();
  void follow_leg();
  void end_job(bool ok, std::string detail);
  void drop_all(const std::string& why);
  [[nodiscard]] std::string aborted() const;

  SmartRobotConfig config_;
  line::Layout layout_;
  const line::RobotSpec* spec_ = nullptr;
  ethercat::master::Master* master_;
  const Clock* clock_;
  Identification identification_;
  std::unique_ptr<smart_robot::Arm> arm_;
  PackMLUnit unit_;
  JobQueue jobs_;
  std::set<std::size_t> empty_;
  bool started_ = false;
  bool auto_start_pending_ = false;
  bool stopped_by_link_ = false;
  ResetStep reset_step_ = ResetStep::enable;
  std::optional<Clock::time_point> enable_since_;  // Resetting's enable step began
  Clock::time_point last_cycle_{};
  std::uint16_t tag_last_ = 0;     // the first station's tag reader, last cycle
  std::uint16_t station_box_ = 0;  // its reading, steady over two cycles (0: none)

  // The job in work on the arm.
  std::unique_ptr<smart_robot::LoadJob> load_;
  std::vector<smart_robot::Leg> legs_;
  std::size_t leg_ = 0;
  bool leg_running_ = false;
  Clock::time_point leg_started_{};
  int placed_ = 0;
};

}  // namespace sf::factory
