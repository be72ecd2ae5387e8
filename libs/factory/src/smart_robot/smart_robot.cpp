#include "sf/factory/smart_robot.hpp"

#include <fmt/format.h>

#include "load_job.hpp"
#include "sf/factory/smart_robot/arm.hpp"

namespace sf::factory {

using S = PackMLState;
using smart_robot::Leg;

namespace {

// The states in which a drive fault aborts the unit: not while it is already going down or
// being cleared, and not in Stopped, where the drives are off and the next Reset acknowledges
// their faults (a fault the drives kept from before, e.g. their watchdog when the previous IPC
// died, is not this controller's to abort on).
bool watches_faults(S s) {
  return s != S::Aborting && s != S::Aborted && s != S::Clearing && s != S::Stopped;
}

// How long Resetting waits for the drives to take the fault reset and enable.
constexpr auto kEnableTimeout = std::chrono::seconds{2};

// The states a lost segment stops (Stop is refused in the others).
bool runs(S s) {
  return s != S::Stopping && s != S::Stopped && s != S::Aborting && s != S::Aborted && s != S::Clearing;
}

std::chrono::nanoseconds seconds(double s) {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::duration<double>(s));
}

}  // namespace

SmartRobot::SmartRobot(SmartRobotConfig config, line::Layout layout, ethercat::master::Master& master,
                       const Clock& clock)
    : config_(std::move(config)),
      layout_(std::move(layout)),
      spec_(layout_.robot(config_.robot)),
      master_(&master),
      clock_(&clock),
      unit_(clock),
      auto_start_pending_(config_.auto_start) {
  identification_.name = config_.robot;
  identification_.kind = "smart-robot";
  if (spec_ != nullptr) {
    identification_.manufacturer = spec_->vendor;
    identification_.model = spec_->model;
    arm_ = std::make_unique<smart_robot::Arm>(master, *spec_, config_.limits, config_.slave);
  }
}

SmartRobot::~SmartRobot() = default;

Status SmartRobot::start() {
  if (spec_ == nullptr || spec_->legacy()) {
    return make_error(Errc::invalid_argument,
                      fmt::format("'{}' is not a smart robot of the layout", config_.robot));
  }
  SF_TRY(motion::validate(config_.limits));
  SF_TRY(master_->bring_up(ethercat::AlState::Op));
  SF_TRY(arm_->attach());
  identification_.serial_number =
      config_.serial_number.empty() ? fmt::format("{}", arm_->serial_number()) : config_.serial_number;
  started_ = true;
  return {};
}

std::vector<std::string> SmartRobot::operations() const {
  return {std::string(kLoad)};
}

// --- the Contract Net's side ------------------------------------------------

std::optional<std::string> SmartRobot::refusal(const Operation& op) const {
  if (!started_ || !arm_->link_up()) {
    return fmt::format("{}'s EtherCAT segment is down: {}", config_.robot,
                       started_ ? arm_->link_error() : "not started");
  }
  if (unit_.state() != S::Execute) {
    return fmt::format("{} is in {}", config_.robot, to_string(unit_.state()));
  }
  if (op.type != kLoad) {
    return fmt::format("{} does not do '{}'", config_.robot, op.type);
  }
  return std::nullopt;
}

std::optional<Estimate> SmartRobot::estimate(const Operation& op, std::string* why_not) const {
  auto fail = [&](std::string why) -> std::optional<Estimate> {
    if (why_not != nullptr) {
      *why_not = std::move(why);
    }
    return std::nullopt;
  };
  if (auto why = refusal(op)) {
    return fail(*why);
  }
  auto job = smart_robot::resolve_load(layout_, *spec_, op);
  if (!job) {
    return fail(job.error().message);
  }
  if (empty_.contains(job->candy)) {
    return fail(fmt::format("{}'s {} dispenser ran empty; an operator's Reset clears it", config_.robot,
                            job->candy_name));
  }
  const auto legs = smart_robot::load_legs(layout_, *spec_, *job, config_.pick_place);
  auto duration =
      smart_robot::load_duration(*spec_, config_.limits, arm_->setpoint(), legs, config_.pick_place);
  if (!duration) {
    return fail(duration.error().message);
  }
  return Estimate{jobs_.backlog(), *duration, jobs_.length()};
}

Status SmartRobot::submit(const std::string& job, const Operation& op) {
  std::string why;
  const auto e = estimate(op, &why);
  return jobs_.admit(config_.robot, job, op, e, why);
}

Status SmartRobot::cancel(const std::string& job) {
  return jobs_.cancel(job);
}

// An operator's command; a Reset starts homing from its first step.
Status SmartRobot::command(PackMLCommand command) {
  SF_TRY(unit_.command(command, operator_stop_reason(command)));
  if (command == PackMLCommand::Reset) {
    reset_step_ = ResetStep::enable;
    enable_since_.reset();
  }
  auto_start_pending_ = false;  // an operator has taken over
  stopped_by_link_ = false;
  return {};
}

ControllerStatus SmartRobot::status() const {
  ControllerStatus s = jobs_.status(unit_);
  if (!started_) {
    s.fault = "not started";
    return s;
  }
  s.fault = arm_->link_up() ? "" : arm_->link_error();
  const auto quality = arm_->link_up() ? Tag::Quality::good : Tag::Quality::bad;
  const std::string reason = arm_->link_up() ? "" : arm_->link_error();
  auto tag = [&](std::string name, decltype(Tag::value) v, std::string unit = {}) {
    s.tags.push_back({std::move(name), std::move(v), quality, reason, std::move(unit)});
  };
  const auto q = arm_->actual();
  const auto axes = arm_->axes();
  for (unsigned a = 0; a < axes.size(); ++a) {
    const std::string axis = fmt::format("axis{}", a + 1);
    // SI, as the joints are computed: metres for z, radians for the others (UNECE codes).
    const std::string unit = a == line::kZAxis ? "MTR" : "C81";
    tag(axis + ".position", q[a], unit);
    tag(axis + ".setpoint", arm_->setpoint()[a], unit);
    tag(axis + ".state", std::string(ethercat::master::cia402::to_string(axes[a].state())));
    tag(axis + ".statusword", static_cast<std::int64_t>(axes[a].statusword()));
  }
  const auto tool = motion::scara_forward(spec_->scara, q).position;
  tag("tool.x", tool.x, "MTR");
  tag("tool.y", tool.y, "MTR");
  tag("tool.z", tool.z, "MTR");
  const std::uint32_t di = arm_->inputs();
  tag("io.gripper", arm_->gripper_on());
  tag("io.part_present", (di & line::kDiPartPresent) != 0);
  tag("io.vacuum_ok", (di & line::kDiVacuumOk) != 0);
  for (std::size_t k = 0; k < spec_->stations.size() && line::kDiBoxInPlace + k < line::kDiBoxId; ++k) {
    tag(fmt::format("io.box_in_place.{}", k), (di & (1U << (line::kDiBoxInPlace + k))) != 0);
  }
  tag("io.station_box", std::int64_t{line::box_id_of(di)});
  return s;
}

// --- the cycle ----------------------------------------------------------------

Clock::time_point SmartRobot::poll(Clock::time_point now) {
  const auto cycle = seconds(config_.limits.cycle);
  if (!started_) {
    return now + cycle;
  }
  arm_->cycle();
  last_cycle_ = now;
  watch_link();
  read_tag();
  // While Resetting acknowledges the drives' faults, they are not new ones.
  const bool acknowledging = unit_.state() == S::Resetting && reset_step_ == ResetStep::enable;
  if (watches_faults(unit_.state()) && !acknowledging && arm_->link_up()) {
    watch_faults();
  }
  auto_start();
  unit_.run(*this);
  for (const auto& outcome : jobs_.take_outcomes()) {
    job_ended(outcome);
  }
  return now + cycle;
}

void SmartRobot::watch_faults() {
  if (auto fault = arm_->axis_fault()) {
    unit_.fault(StopReason{kStopAxisFault, fmt::format("{}: {}", config_.robot, *fault), {}});
  }
}

// A lost segment stops the unit; once the slave is back in OP the controller resets by itself.
void SmartRobot::watch_link() {
  if (!arm_->link_up()) {
    if (runs(unit_.state())) {
      (void)unit_.command(
          PackMLCommand::Stop,
          StopReason{kStopEtherCatLost, fmt::format("{}: {}", config_.robot, arm_->link_error()), {}});
      stopped_by_link_ = true;
    }
    return;
  }
  if (stopped_by_link_ && unit_.state() == S::Stopped) {
    stopped_by_link_ = false;
    reset_step_ = ResetStep::enable;
    enable_since_.reset();
    (void)unit_.command(PackMLCommand::Reset);
    auto_start_pending_ = config_.auto_start;
  }
}

void SmartRobot::auto_start() {
  if (!auto_start_pending_ || !arm_->link_up()) {
    return;
  }
  if (unit_.state() == S::Stopped) {
    reset_step_ = ResetStep::enable;
    enable_since_.reset();
  }
  if (unit_.advance_to_execute()) {
    auto_start_pending_ = false;
  }
}

void SmartRobot::execute() {
  work(true);
}

bool SmartRobot::wind_down() {
  work(false);
  return !leg_running_ || !arm_->link_up();
}

void SmartRobot::stopped() {
  arm_->halt();
  arm_->gripper(false);
  drop_all("stopped");
}

void SmartRobot::abort() {
  arm_->disable();
  arm_->gripper(false);
  drop_all(aborted());
}

// Wait states: finish the move in progress, start nothing.
void SmartRobot::wait() {
  if (leg_running_) {
    work(false);
  }
}

// Resetting: drive faults acknowledged, drives enabled where they stand, then home.
bool SmartRobot::reset() {
  if (!arm_->link_up()) {
    return false;
  }
  switch (reset_step_) {
    case ResetStep::enable:
      if (!enable_since_) {
        enable_since_ = clock_->now();
      } else if (clock_->now() - *enable_since_ > kEnableTimeout) {
        const auto fault = arm_->axis_fault();
        unit_.fault(StopReason{kStopAxisFault,
                               fmt::format("{}: the drives did not enable: {}", config_.robot,
                                           fault ? *fault : std::string("no fault shown")),
                               {}});
        return false;
      }
      empty_.clear();
      arm_->fault_reset();
      arm_->gripper(false);
      arm_->enable();
      if (arm_->enabled()) {
        const motion::Vec3 home = smart_robot::home_point(layout_, *spec_);
        const auto here = motion::scara_forward(spec_->scara, arm_->setpoint()).position;
        // Up first, then across: the tool never sweeps low over the belt.
        auto waypoints = smart_robot::from_here(
            here, {motion::Waypoint{{{here.x, here.y, std::max(here.z, home.z)}, 0.0}, 0.0, 0.0},
                   motion::Waypoint{{home, 0.0}, 0.0, 0.0}});
        if (!waypoints.empty()) {
          auto path = arm_->plan(waypoints);
          if (!path) {
            unit_.fault(StopReason{
                kStopHomingFailed, fmt::format("{}: homing: {}", config_.robot, path.error().message), {}});
            return false;
          }
          arm_->follow(std::move(*path));
        }
        reset_step_ = ResetStep::home;
        enable_since_.reset();
      }
      return false;
    case ResetStep::home:
      if (!arm_->settled()) {
        return false;
      }
      reset_step_ = ResetStep::done;
      return true;
    case ResetStep::done:
      return true;
  }
  return false;
}

// Clearing: the drives' faults acknowledged; done once none is left.
bool SmartRobot::clear() {
  arm_->fault_reset();
  return !arm_->axis_fault();
}

std::string SmartRobot::aborted() const {
  const auto reason = unit_.status().stop_reason;
  return reason ? fmt::format("aborted ({})", reason->message) : "aborted";
}

// --- jobs ---------------------------------------------------------------------

void SmartRobot::work(bool go) {
  if (!load_) {
    if (!go || !begin_job()) {
      return;
    }
  }
  QueuedJob* job = jobs_.current();
  if (go) {
    job->active += seconds(config_.limits.cycle);
    if (job->active > job->estimate + config_.job_timeout) {
      arm_->halt();
      arm_->gripper(false);
      const auto late = std::chrono::duration<double>(job->active - job->estimate).count();
      return end_job(false, fmt::format("timed out ({:.1f} s over its estimate)", late));
    }
  }
  if (leg_running_) {
    follow_leg();
    return;
  }
  if (!go) {
    return;
  }
  if (job->cancel && !arm_->gripper_on()) {  // never with a part on the cup
    return end_job(false, "cancelled");
  }
  if (leg_ == legs_.size()) {
    return end_job(true, fmt::format("{} {} in slots {}-{} of box {}", load_->count, load_->candy_name,
                                     load_->first_slot, load_->first_slot + load_->count - 1, load_->box));
  }
  begin_leg();
}

void SmartRobot::read_tag() {
  const std::uint16_t now = arm_->link_up() ? line::box_id_of(arm_->inputs()) : 0;
  station_box_ = now == tag_last_ ? now : 0;  // a box passing through is not in place
  tag_last_ = now;
}

// A load is ready once its box stands at its station.
bool SmartRobot::box_ready(const Operation& op) const {
  const auto box = op.param("box");
  const std::size_t station = static_cast<std::size_t>(op.param("station").value_or(0));
  if (station == 0) {
    return box && station_box_ != 0 && *box == station_box_;
  }
  // No tag reader at the robot's other stations: their box-in-place input.
  return line::kDiBoxInPlace + station < line::kDiBoxId &&
         (arm_->inputs() & (1U << (line::kDiBoxInPlace + station))) != 0;
}

bool SmartRobot::begin_job() {
  if (!jobs_.begin_next([this](const Operation& op) { return box_ready(op); })) {
    return false;
  }
  auto job = smart_robot::resolve_load(layout_, *spec_, jobs_.current()->op);
  if (!job) {
    end_job(false, job.error().message);
    return false;
  }
  load_ = std::make_unique<smart_robot::LoadJob>(*job);
  legs_ = smart_robot::load_legs(layout_, *spec_, *load_, config_.pick_place);
  leg_ = 0;
  leg_running_ = false;
  placed_ = 0;
  return true;
}

void SmartRobot::begin_leg() {
  const Leg& leg = legs_[leg_];
  leg_started_ = clock_->now();
  leg_running_ = true;
  switch (leg.kind) {
    case Leg::Kind::grip:
      arm_->gripper(true);
      return;
    case Leg::Kind::release:
      arm_->gripper(false);
      return;
    case Leg::Kind::move: {
      const auto here = motion::scara_forward(spec_->scara, arm_->setpoint()).position;
      const auto waypoints = smart_robot::from_here(here, leg.waypoints);
      if (waypoints.empty()) {
        return;
      }
      auto path = arm_->plan(waypoints);
      if (!path) {
        leg_running_ = false;
        return end_job(false, fmt::format("move {}: {}", leg_ + 1, path.error().message));
      }
      arm_->follow(std::move(*path));
      return;
    }
  }
}

void SmartRobot::follow_leg() {
  const Leg& leg = legs_[leg_];
  const auto waited = clock_->now() - leg_started_;
  const std::uint32_t di = arm_->inputs();
  switch (leg.kind) {
    case Leg::Kind::move:
      if (!arm_->move_error().empty()) {
        leg_running_ = false;
        return end_job(false, fmt::format("move {}: {}", leg_ + 1, arm_->move_error()));
      }
      if (!arm_->settled()) {
        return;
      }
      break;
    case Leg::Kind::grip:
      if ((di & (line::kDiPartPresent | line::kDiVacuumOk)) != (line::kDiPartPresent | line::kDiVacuumOk)) {
        if (waited < config_.pick_place.grip_timeout) {
          return;
        }
        arm_->gripper(false);
        empty_.insert(load_->candy);
        leg_running_ = false;
        return end_job(
            false,
            fmt::format("no {} on the cup {} ms after the pick at {}: the dispenser is empty",
                        load_->candy_name, config_.pick_place.grip_timeout.count(), load_->dispenser->name));
      }
      break;
    case Leg::Kind::release:
      if ((di & line::kDiPartPresent) != 0) {
        if (waited < config_.pick_place.release_timeout) {
          return;
        }
        leg_running_ = false;
        unit_.fault(StopReason{kStopPartStuck,
                               fmt::format("{}: the {} does not leave the cup over slot {}", config_.robot,
                                           load_->candy_name, load_->first_slot + leg.candy),
                               {}});
        return;
      }
      ++placed_;
      break;
  }
  leg_running_ = false;
  ++leg_;
}

void SmartRobot::end_job(bool ok, std::string detail) {
  unit_.count(ok);
  if (!ok && placed_ > 0) {
    detail += fmt::format(" ({} of {} placed)", placed_, load_ ? load_->count : 0);
  }
  jobs_.finish(ok, std::move(detail));
  load_.reset();
  legs_.clear();
  leg_running_ = false;
}

void SmartRobot::drop_all(const std::string& why) {
  if (jobs_.current() != nullptr) {
    end_job(false, why);
  }
  jobs_.drop_queued(why);
}

}  // namespace sf::factory
