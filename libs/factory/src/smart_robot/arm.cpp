#include "sf/factory/smart_robot/arm.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>

#include <fmt/format.h>

namespace sf::factory::smart_robot {

namespace {

// Objects of axis n sit at index + 0x800·n (ETG.6010 multi-axis layout).
constexpr std::uint16_t kErrorCode = 0x603F;
constexpr std::uint16_t kAxisStride = 0x800;
// CiA 402's position window (0x6067) as the controller checks it: counts
// between set-point and actual position for a move to count as done.
constexpr std::int64_t kInPosition = 20;

// Cycles in a row whose frame did not come back (or came back with a short
// working counter) before the link counts as down: a single lost frame is
// the network's business, 10 ms without one is a cut cable.
constexpr unsigned kLostCycles = 10;

}  // namespace

Arm::Arm(ethercat::master::Master& master, const line::RobotSpec& spec, motion::MotionLimits limits,
         std::size_t slave)
    : master_(&master), spec_(&spec), limits_(limits), slave_(slave) {}

Status Arm::attach() {
  std::vector<ethercat::master::Cia402Axis> axes;
  for (unsigned a = 0; a < line::kArmAxes; ++a) {
    auto axis = ethercat::master::Cia402Axis::attach(*master_, slave_, a);
    if (!axis) {
      return Error(axis.error()).with_context(fmt::format("axis {}", a + 1));
    }
    axes.push_back(std::move(*axis));
  }
  auto out = master_->slave(slave_).entry(0x7000, 0);
  auto in = master_->slave(slave_).entry(0x6000, 0);
  if (!out || !in) {
    return make_error(Errc::not_found, "the smart controller maps no digital IO (0x7000, 0x6000)");
  }
  axes_ = std::move(axes);
  do_ = *out;
  di_ = *in;
  master_->on_slave_event([this](const ethercat::master::SlaveEvent& e) {
    if (e.position != slave_) {
      return;
    }
    slave_down_ = e.kind != ethercat::master::SlaveEvent::Kind::recovered;
    if (slave_down_) {
      link_error_ = e.message;
    }
  });
  link_up_ = true;
  slave_down_ = false;
  failed_cycles_ = 0;
  link_error_.clear();
  return {};
}

std::uint32_t Arm::serial_number() const {
  const auto& slaves = master_->slaves();
  return slave_ < slaves.size() ? slaves[slave_].sii.identity.serial : 0;
}

void Arm::cycle() {
  const auto result = master_->exchange();
  // Cheap while the segment is healthy; drives a lost slave's recovery (its
  // frames may well come back complete without it).
  master_->maintain();
  failed_cycles_ = result.ok() ? 0 : failed_cycles_ + 1;
  if (axes_.empty()) {
    return;
  }
  update_link(result);
  auto view = master_->slave(slave_);
  inputs_ = view.get<std::uint32_t>(di_);
  sample();
  write_setpoint();
  for (auto& axis : axes_) {
    axis.update();
  }
  if (!moving()) {
    std::array<double, line::kArmAxes> counts{};
    for (unsigned a = 0; a < line::kArmAxes; ++a) {
      counts[a] = axes_[a].target_position();
    }
    setpoint_ = line::joints_from_counts(counts);
  }
  view.set<std::uint32_t>(do_, link_up_ ? outputs_ : 0U);
}

void Arm::update_link(const ethercat::master::ExchangeResult& result) {
  const bool up = !slave_down_ && failed_cycles_ < kLostCycles;
  if (!up && failed_cycles_ >= kLostCycles && !slave_down_) {
    link_error_ = result.received
                      ? fmt::format("{} cycles in a row with working counter {} of {}", failed_cycles_,
                                    result.wkc, result.expected_wkc)
                      : fmt::format("{} cyclic frames in a row did not come back", failed_cycles_);
  }
  if (up) {
    link_error_.clear();
  }
  link_up_ = up;
}

void Arm::sample() {
  if (!sampler_) {
    return;
  }
  if (!enabled() || !link_up_) {
    halt();
    move_error_ = link_up_ ? drive_not_enabled() : link_error_;
    return;
  }
  motion::ScaraJoints next = setpoint_;
  if (sampler_->next(next)) {
    setpoint_ = next;
    return;
  }
  if (auto fault = sampler_->fault(); !fault) {
    move_error_ = fault.error().message;
  }
  sampler_.reset();
  path_.reset();
}

std::string Arm::drive_not_enabled() const {
  for (unsigned a = 0; a < axes_.size(); ++a) {
    if (!axes_[a].enabled()) {
      return fmt::format("axis {} ({}) left operation enabled: {}", a + 1, motion::kScaraJointNames.at(a),
                         ethercat::master::cia402::to_string(axes_[a].state()));
    }
  }
  return "a drive left operation enabled";
}

void Arm::write_setpoint() {
  if (!moving()) {
    return;
  }
  const auto counts = line::counts_from_joints(setpoint_);
  for (unsigned a = 0; a < line::kArmAxes; ++a) {
    axes_[a].set_target_position(counts[a]);
  }
}

void Arm::enable() {
  for (auto& axis : axes_) {
    axis.set_target_position(axis.actual_position());
    axis.enable();
  }
}

void Arm::disable() {
  halt();
  for (auto& axis : axes_) {
    axis.disable();
  }
}

void Arm::fault_reset() {
  error_codes_ = {};
  for (auto& axis : axes_) {
    if (axis.fault()) {
      axis.fault_reset();
    }
  }
}

bool Arm::enabled() const {
  return !axes_.empty() && std::all_of(axes_.begin(), axes_.end(), [](const auto& a) { return a.enabled(); });
}

std::optional<std::string> Arm::axis_fault() {
  for (unsigned a = 0; a < axes_.size(); ++a) {
    if (!axes_[a].fault()) {
      continue;
    }
    if (!error_codes_[a]) {
      const auto index = static_cast<std::uint16_t>(kErrorCode + kAxisStride * a);
      auto code = master_->sdo_read<std::uint16_t>(slave_, index, 0);
      error_codes_[a] = code ? *code : 0;
    }
    return fmt::format("axis {} ({}) fault, error code 0x{:04X}", a + 1, motion::kScaraJointNames.at(a),
                       *error_codes_[a]);
  }
  return std::nullopt;
}

Result<motion::CartesianPath> Arm::plan(std::span<const motion::Waypoint> waypoints) const {
  return plan_from(setpoint_, waypoints);
}

Result<motion::CartesianPath> Arm::plan_from(const motion::ScaraJoints& start,
                                             std::span<const motion::Waypoint> waypoints) const {
  return motion::plan_path(spec_->scara, limits_, start, waypoints);
}

void Arm::follow(motion::CartesianPath path) {
  sampler_.reset();
  path_ = std::move(path);
  sampler_.emplace(*path_);
  move_error_.clear();
}

void Arm::halt() {
  sampler_.reset();
  path_.reset();
}

bool Arm::settled() const {
  if (moving()) {
    return false;
  }
  const auto target = line::counts_from_joints(setpoint_);
  for (unsigned a = 0; a < axes_.size(); ++a) {
    if (std::llabs(static_cast<long long>(axes_[a].actual_position()) - target[a]) > kInPosition) {
      return false;
    }
  }
  return true;
}

motion::ScaraJoints Arm::actual() const {
  std::array<double, line::kArmAxes> counts{};
  for (unsigned a = 0; a < axes_.size(); ++a) {
    counts[a] = axes_[a].actual_position();
  }
  return line::joints_from_counts(counts);
}

}  // namespace sf::factory::smart_robot
