// The closed controller of a legacy robot (plc.hpp, registers.hpp): it runs
// a job with its own moves, straight lines of the tool at the arm's speed,
// and grips and releases through the world like any gripper.
#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "sf/plant/plc.hpp"

namespace sf::plant {

namespace {

constexpr double kApproach = 0.05;    // m above a pick or place point
constexpr double kPlaceAbove = 0.01;  // m above the box top when releasing
constexpr double kHomeAbove = 0.15;   // m above the first station
constexpr double kDwell = 0.15;       // s the gripper needs to close or open
constexpr double kArrived = 1e-6;     // m

std::int16_t milli(double v) {
  return static_cast<std::int16_t>(std::lround(std::clamp(v * 1000.0, -32768.0, 32767.0)));
}

motion::Vec3 above(motion::Vec3 p, double dz) {
  return {p.x, p.y, p.z + dz};
}

}  // namespace

RobotControllerPlc::RobotControllerPlc(World& world, std::size_t robot)
    : PlcDevice(world.layout().robots.at(robot).name, robot_bank_layout()), robot_(robot) {
  const Layout& layout = world.layout();
  const RobotSpec& spec = layout.robots[robot];
  const StationRef first = *find_station(layout, spec.stations.front());
  const BeltSpec& belt = layout.belts[first.belt];
  const motion::Vec2 p = belt.point_at(belt.stations[first.station].at_m);
  home_ = {p.x, p.y, belt.height_m + kHomeAbove};
  joints_.assign(spec.kind == RobotKind::legacy_articulated ? 6 : 4, 0.0);
  set_tool(world, home_);
  publish(world);
}

int RobotControllerPlc::dispenser_for(const World& world, std::size_t candy) const {
  const Layout& layout = world.layout();
  int found = -1;
  for (const auto& name : layout.robots[robot_].dispensers) {
    for (std::size_t d = 0; d < layout.dispensers.size(); ++d) {
      if (layout.dispensers[d].name != name ||
          layout.dispensers[d].candy != layout.catalog.candy_types[candy].name) {
        continue;
      }
      if (world.stock(d) > 0) {
        return static_cast<int>(d);
      }
      found = found < 0 ? static_cast<int>(d) : found;  // an empty one, if no other
    }
  }
  return found;
}

void RobotControllerPlc::run(World& world, double dt) {
  if (job_.scan(bank_)) {
    begin(world);
  }
  if (job_.phase() == JobHandshake::Phase::busy) {
    move(world, dt);
  } else if (job_.phase() == JobHandshake::Phase::fault && next_ < plan_.size()) {
    move(world, dt);  // after a failure the arm still goes home
  }
  world.heat_drives(robot_, dt, job_.phase() == JobHandshake::Phase::busy || next_ < plan_.size());
  fault_code_ = job_.code();
  publish(world);
}

void RobotControllerPlc::begin(World& world) {
  using namespace robot_controller;
  const Layout& layout = world.layout();
  const RobotSpec& spec = layout.robots[robot_];
  const std::uint16_t candy = bank_.holding_register(kCandyType);
  const std::uint16_t slot = bank_.holding_register(kSlot);
  const std::uint16_t station = bank_.holding_register(kStation);
  plan_.clear();
  next_ = 0;
  if (candy == 0 || candy > layout.catalog.candy_types.size() || station >= spec.stations.size()) {
    return fail(world, FaultCode::bad_job,
                fmt::format("candy type {} or station {} unknown", candy, station));
  }
  const int dispenser = dispenser_for(world, candy - 1U);
  if (dispenser < 0) {
    return fail(world, FaultCode::bad_job,
                fmt::format("no dispenser of {}", layout.catalog.candy_types[candy - 1U].name));
  }
  const StationRef ref = *find_station(layout, spec.stations[station]);
  const Box* box = world.box_in_place(ref.belt, ref.station);
  if (box == nullptr) {
    return fail(world, FaultCode::no_box, "no box in place at " + spec.stations[station]);
  }
  if (slot >= box->slots.size()) {
    return fail(world, FaultCode::bad_job, fmt::format("box {} has no slot {}", box->id, slot));
  }
  const motion::Vec3 pick = layout.dispensers[static_cast<std::size_t>(dispenser)].at;
  const motion::Vec3 place = above(world.slot_position(*box, slot), kPlaceAbove);
  if (!spec.reaches(pick) || !spec.reaches(place) || !spec.reaches(above(place, kApproach))) {
    return fail(world, FaultCode::unreachable, "pick or place point out of reach");
  }
  using Action = Waypoint::Action;
  plan_ = {{above(pick, kApproach)},
           {pick, Action::grip},
           {above(pick, kApproach), Action::check_part},
           {above(place, kApproach)},
           {place, Action::release},
           {above(place, kApproach)},
           {home_}};
  world.record(EventKind::job_started, spec.name, box->id, slot, layout.catalog.candy_types[candy - 1U].name);
}

void RobotControllerPlc::move(World& world, double dt) {
  if (dwell_s_ > 0.0) {
    dwell_s_ -= dt;
    return;
  }
  if (next_ >= plan_.size()) {
    return;
  }
  const Waypoint& target = plan_[next_];
  const motion::Vec3 from = world.tool(robot_).pose.position;
  const motion::Vec3 d = target.at - from;
  const double distance = motion::norm(d);
  const double step = world.layout().robots[robot_].tool_speed_mps * dt;
  if (distance > step + kArrived) {
    set_tool(world, from + (step / distance) * d);
    return;
  }
  set_tool(world, target.at);
  ++next_;
  arrive(world, target);
}

void RobotControllerPlc::arrive(World& world, const Waypoint& waypoint) {
  using Action = Waypoint::Action;
  switch (waypoint.action) {
    case Action::grip:
      world.set_gripper(robot_, true);
      dwell_s_ = kDwell;
      return;
    case Action::release:
      world.set_gripper(robot_, false);
      dwell_s_ = kDwell;
      return;
    case Action::check_part:
      if (world.tool(robot_).held < 0) {
        world.set_gripper(robot_, false);
        return fail(world, FaultCode::dispenser_empty, "no part in the gripper after the pick");
      }
      return;
    case Action::none:
      break;
  }
  if (next_ == plan_.size() && job_.phase() == JobHandshake::Phase::busy) {
    ++jobs_done_;
    job_.finish();
    world.record(EventKind::job_done, world.layout().robots[robot_].name);
  }
}

void RobotControllerPlc::fail(World& world, FaultCode code, const std::string& why) {
  job_.fail(code);
  world.record(EventKind::job_failed, world.layout().robots[robot_].name, 0, -1, {},
               fmt::format("{}: {}", to_string(code), why));
  plan_ = {{above(world.tool(robot_).pose.position, kApproach)}, {home_}};
  next_ = 0;
}

void RobotControllerPlc::set_tool(World& world, const motion::Vec3& at) {
  const RobotSpec& spec = world.layout().robots[robot_];
  const motion::ToolPose pose{at, 0.0};
  if (spec.kind == RobotKind::legacy_articulated) {
    if (auto q = motion::articulated_inverse(spec.articulated, pose)) {
      joints_.assign(q->begin(), q->end());
    }
  } else {
    motion::ScaraJoints current{};
    std::copy_n(joints_.begin(), current.size(), current.begin());
    if (auto q = motion::scara_inverse_nearest(spec.scara, pose, current)) {
      joints_.assign(q->begin(), q->end());
    }
  }
  world.set_tool(robot_, pose, joints_);
}

void RobotControllerPlc::publish(const World& world) {
  using namespace robot_controller;
  job_.publish(bank_);
  const Tool& tool = world.tool(robot_);
  bank_.set_discrete_input(kPartPresent, tool.held >= 0);
  const auto& stations = world.layout().robots[robot_].stations;
  for (std::size_t k = 0; k < stations.size() && k < kMaxRepeats; ++k) {
    const StationRef ref = *find_station(world.layout(), stations[k]);
    bank_.set_discrete_input(static_cast<std::uint16_t>(kBoxInPlace + k),
                             world.box_in_place(ref.belt, ref.station) != nullptr);
    bank_.set_input_register(static_cast<std::uint16_t>(kStationBox + k),
                             world.tag_reading(ref.belt, ref.station));
  }
  bank_.set_input_register(kFaultCode, static_cast<std::uint16_t>(job_.code()));
  bank_.set_input_register(kJobsDone, jobs_done_);
  for (std::size_t j = 0; j < joints_.size() && j < 6; ++j) {
    bank_.set_input_register(static_cast<std::uint16_t>(kJoint + j),
                             static_cast<std::uint16_t>(milli(joints_[j])));
  }
  bank_.set_input_register(kToolX, static_cast<std::uint16_t>(milli(tool.pose.position.x)));
  bank_.set_input_register(kToolY, static_cast<std::uint16_t>(milli(tool.pose.position.y)));
  bank_.set_input_register(kToolZ, static_cast<std::uint16_t>(milli(tool.pose.position.z)));
  bank_.set_input_register(kTemperature,
                           static_cast<std::uint16_t>(std::lround(tool.drive_temperature_c * 10.0)));
  bank_.set_input_register(
      kPhase, static_cast<std::uint16_t>(job_.phase() == JobHandshake::Phase::busy ? next_ + 1 : 0));
}

}  // namespace sf::plant
