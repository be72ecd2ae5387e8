#include "sf/plant/smart_robot.hpp"

#include <cmath>
#include <mutex>

namespace sf::plant {

namespace {
constexpr double kParkAbove = 0.15;  // m above the first station
}

SmartRobotCell::SmartRobotCell(World& world, std::size_t robot, const Clock& clock, std::uint32_t serial)
    : robot_(robot), name_(world.layout().robots.at(robot).name) {
  const Layout& layout = world.layout();
  const RobotSpec& spec = layout.robots[robot];
  segment_ = std::make_unique<ethercat::slave::Segment>(clock);
  ethercat::slave::DeviceOptions options;
  options.serial = serial;
  segment_->add(std::make_unique<ethercat::slave::SmartController>(options));
  // Park: the tool raised over the first station, elbow as the IK prefers.
  const StationRef first = *find_station(layout, spec.stations.front());
  const BeltSpec& belt = layout.belts[first.belt];
  const motion::Vec2 p = belt.point_at(belt.stations[first.station].at_m);
  const motion::ToolPose park{{p.x, p.y, belt.height_m + kParkAbove}, 0.0};
  auto q = motion::scara_inverse_nearest(spec.scara, park, {0.0, 0.5, 0.0, 0.0});
  const auto counts = counts_from_joints(q ? *q : motion::ScaraJoints{});
  for (unsigned a = 0; a < kArmAxes; ++a) {
    controller().axis(a).set_position(counts[a]);
  }
  scan(world);
}

ethercat::slave::SmartController& SmartRobotCell::controller() {
  return *segment_->device<ethercat::slave::SmartController>(0);
}

void SmartRobotCell::scan(World& world) {
  const RobotSpec& spec = world.layout().robots[robot_];
  auto lock = segment_->lock();
  auto& device = controller();
  std::array<double, kArmAxes> counts{};
  for (unsigned a = 0; a < kArmAxes; ++a) {
    counts[a] = device.axis(a).position();
  }
  const motion::ScaraJoints q = joints_from_counts(counts);
  world.set_tool(robot_, motion::scara_forward(spec.scara, q), {q.begin(), q.end()});
  world.set_gripper(robot_, (device.digital_outputs() & kDoGripper) != 0);
  const Tool& tool = world.tool(robot_);
  std::uint32_t inputs = 0;
  if (tool.held >= 0) {
    inputs |= kDiPartPresent;
    inputs |= tool.gripper ? kDiVacuumOk : 0U;
  }
  for (std::size_t k = 0; k < spec.stations.size() && kDiBoxInPlace + k < kDiBoxId; ++k) {
    const StationRef ref = *find_station(world.layout(), spec.stations[k]);
    if (world.box_in_place(ref.belt, ref.station) != nullptr) {
      inputs |= 1U << (kDiBoxInPlace + k);
    }
  }
  // The first station's tag reader, wired in parallel onto the upper half of the inputs.
  const StationRef first = *find_station(world.layout(), spec.stations.front());
  inputs |= std::uint32_t{world.tag_reading(first.belt, first.station)} << kDiBoxId;
  device.set_digital_inputs(inputs);
}

void SmartRobotCell::axis_fault(unsigned axis, std::uint16_t error_code) {
  auto lock = segment_->lock();
  controller().axis(axis).inject_fault(error_code);
}

void SmartRobotCell::cut_cable() {
  segment_->disconnect(0);
  cable_cut_ = true;
}

void SmartRobotCell::restore_cable() {
  segment_->reconnect(0);
  cable_cut_ = false;
}

}  // namespace sf::plant
