#include "load_job.hpp"

#include <cmath>

#include <fmt/format.h>

namespace sf::factory::smart_robot {

namespace {

// Where a legacy controller waits too: 15 cm above the belt (plant robot controllers).
constexpr double kHomeAbove = 0.15;
// Closer than this to the tool, a way-point is where the tool already is.
constexpr double kSamePoint = 1e-4;

motion::Vec3 above(motion::Vec3 p, double dz) {
  return {p.x, p.y, p.z + dz};
}

motion::Waypoint through(motion::Vec3 p, double blend) {
  return motion::Waypoint{motion::ToolPose{p, 0.0}, blend, 0.0};
}

motion::Waypoint stop_at(motion::Vec3 p) {
  return motion::Waypoint{motion::ToolPose{p, 0.0}, 0.0, 0.0};
}

double distance(const motion::Vec3& a, const motion::Vec3& b) {
  return std::hypot(a.x - b.x, a.y - b.y, a.z - b.z);
}

const line::DispenserSpec* dispenser_of(const line::Layout& layout, const line::RobotSpec& robot,
                                        const std::string& candy) {
  for (const auto& name : robot.dispensers) {
    const line::DispenserSpec* d = layout.dispenser(name);
    if (d != nullptr && d->candy == candy) {
      return d;
    }
  }
  return nullptr;
}

}  // namespace

Result<LoadJob> resolve_load(const line::Layout& layout, const line::RobotSpec& robot, const Operation& op) {
  const auto& catalog = layout.catalog;
  auto candy = op.integer("candy", 0, static_cast<std::int64_t>(catalog.candy_types.size()) - 1);
  auto type = op.integer("box_type", 0, static_cast<std::int64_t>(catalog.box_types.size()) - 1);
  auto box = op.integer("box", 1, 0xFFFF);
  auto station = op.param("station")
                     ? op.integer("station", 0, static_cast<std::int64_t>(robot.stations.size()) - 1)
                     : Result<std::int64_t>(0);
  for (const auto* r : {&candy, &type, &box, &station}) {
    if (!*r) {
      return r->error();
    }
  }
  LoadJob job;
  job.candy = static_cast<std::size_t>(*candy);
  job.candy_name = catalog.candy_types[job.candy].name;
  job.box_type = &catalog.box_types[static_cast<std::size_t>(*type)];
  auto count = op.param("count") ? op.integer("count", 1, job.box_type->capacity()) : Result<std::int64_t>(1);
  auto slot = op.integer("slot", 0, job.box_type->capacity() - 1);
  for (const auto* r : {&count, &slot}) {
    if (!*r) {
      return r->error();
    }
  }
  if (*slot + *count > job.box_type->capacity()) {
    return make_error(Errc::invalid_argument,
                      fmt::format("load: slots {}..{} do not fit a {} ({} slots)", *slot, *slot + *count - 1,
                                  job.box_type->name, job.box_type->capacity()));
  }
  job.dispenser = dispenser_of(layout, robot, job.candy_name);
  if (job.dispenser == nullptr) {
    return make_error(Errc::unsupported,
                      fmt::format("{} has no dispenser of {}", robot.name, job.candy_name));
  }
  job.count = static_cast<int>(*count);
  job.first_slot = static_cast<int>(*slot);
  job.box = static_cast<std::uint32_t>(*box);
  job.station_index = static_cast<std::size_t>(*station);
  auto ref = line::find_station(layout, robot.stations.at(job.station_index));
  if (!ref) {
    return ref.error();
  }
  job.station = *ref;
  return job;
}

motion::Vec3 home_point(const line::Layout& layout, const line::RobotSpec& robot) {
  if (robot.home) {
    return *robot.home;
  }
  auto ref = line::find_station(layout, robot.stations.at(0));
  const line::BeltSpec& belt = layout.belts.at(ref->belt);
  const motion::Vec2 p = belt.point_at(belt.stations.at(ref->station).at_m);
  return {p.x, p.y, belt.height_m + kHomeAbove};
}

std::vector<Leg> load_legs(const line::Layout& layout, const line::RobotSpec& robot, const LoadJob& job,
                           const PickPlace& how) {
  const motion::Vec3 home = home_point(layout, robot);
  const motion::Vec3 pick = job.dispenser->at;
  std::vector<Leg> legs;
  for (int i = 0; i < job.count; ++i) {
    const motion::Vec3 slot = line::slot_point(layout, job.station, *job.box_type, job.first_slot + i);
    legs.push_back(
        {Leg::Kind::move,
         {through(home, how.blend_m), through(above(pick, how.approach_m), how.blend_m), stop_at(pick)},
         i});
    legs.push_back({Leg::Kind::grip, {}, i});
    legs.push_back({Leg::Kind::move,
                    {through(above(pick, how.approach_m), how.blend_m), through(home, how.blend_m),
                     through(above(slot, how.approach_m), how.blend_m), stop_at(above(slot, how.release_m))},
                    i});
    legs.push_back({Leg::Kind::release, {}, i});
    legs.push_back({Leg::Kind::move, {stop_at(above(slot, how.approach_m))}, i});
  }
  legs.push_back({Leg::Kind::move, {stop_at(home)}, job.count - 1});
  return legs;
}

std::vector<motion::Waypoint> from_here(const motion::Vec3& here,
                                        const std::vector<motion::Waypoint>& waypoints) {
  std::vector<motion::Waypoint> out;
  motion::Vec3 at = here;
  for (auto& w : waypoints) {
    if (distance(at, w.pose.position) > kSamePoint) {
      at = w.pose.position;
      out.push_back(w);
    }
  }
  return out;
}

Result<std::chrono::nanoseconds> load_duration(const line::RobotSpec& robot,
                                               const motion::MotionLimits& limits,
                                               const motion::ScaraJoints& start, const std::vector<Leg>& legs,
                                               const PickPlace& how) {
  std::chrono::nanoseconds total{0};
  motion::ScaraJoints at = start;
  for (std::size_t i = 0; i < legs.size(); ++i) {
    const Leg& leg = legs[i];
    if (leg.kind != Leg::Kind::move) {
      total += leg.kind == Leg::Kind::grip ? how.grip_time : how.release_time;
      continue;
    }
    const auto waypoints = from_here(motion::scara_forward(robot.scara, at).position, leg.waypoints);
    if (waypoints.empty()) {
      continue;
    }
    auto path = motion::plan_path(robot.scara, limits, at, waypoints);
    if (!path) {
      return Error(path.error()).with_context(fmt::format("move {} of the job", i + 1));
    }
    total +=
        std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::duration<double>(path->duration()));
    at = path->end_joints();
  }
  return total;
}

}  // namespace sf::factory::smart_robot
