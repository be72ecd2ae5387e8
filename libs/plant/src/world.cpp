// World (world.hpp): time, boxes on and off the line, dispensers, tools.
// Belt motion is in belts.cpp.
#include "sf/plant/world.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

namespace sf::plant {

namespace {
constexpr double kSlotDepth = 0.005;     // m: a tool this far below the box top is still over the slot
constexpr double kReleaseHeight = 0.03;  // m: above the box top a released candy still lands in its slot
}  // namespace

World::World(Layout layout, std::uint64_t seed) : layout_(std::move(layout)), rng_(seed) {
  for (const auto& b : layout_.belts) {
    BeltState state;
    state.speed_mps = b.speed_mps;
    state.stoppers.assign(b.stations.size(), false);
    belts_.push_back(std::move(state));
  }
  for (const auto& d : layout_.dispensers) {
    stock_.push_back(d.stock);
  }
  mixed_up_.assign(layout_.dispensers.size(), false);
  for (const auto& type : layout_.catalog.box_types) {
    max_half_ = std::max(max_half_, type.size_m.x / 2.0);
  }
  on_belt_.resize(layout_.belts.size());
  feeders_.resize(layout_.belts.size());
  next_.resize(layout_.belts.size());
  for (std::size_t b = 0; b < layout_.belts.size(); ++b) {
    length_.push_back(layout_.belts[b].length());
    for (const auto& next : layout_.belts[b].next) {
      if (auto n = layout_.belt_index(next)) {
        feeders_[*n].push_back(b);
        next_[b].push_back(*n);
      }
    }
  }
  for (const auto& r : layout_.robots) {
    Tool tool;
    const motion::Vec3 base = r.kind == RobotKind::legacy_articulated ? r.articulated.base : r.scara.base;
    tool.pose.position = base;
    tools_.push_back(std::move(tool));
  }
}

void World::advance(std::chrono::nanoseconds dt) {
  pending_ += dt;
  while (pending_ >= kWorldStep) {
    pending_ -= kWorldStep;
    step();
  }
}

void World::step() {
  ++steps_;
  time_ += kWorldStep;
  const double dt = std::chrono::duration<double>(kWorldStep).count();
  for (std::size_t b = 0; b < belts_.size(); ++b) {
    move_belt(b, dt);
  }
  reindex();
}

void World::record(EventKind kind, std::string where, BoxId box, int slot, std::string candy,
                   std::string detail) {
  events_.add(Event{time_, kind, std::move(where), box, slot, std::move(candy), std::move(detail)});
}

std::string World::station_name(std::size_t b, std::size_t station) const {
  return layout_.belts[b].name + "/" + layout_.belts[b].stations[station].name;
}

// --- belts -----------------------------------------------------------------

void World::set_motor(std::size_t b, bool on, bool reverse) {
  belts_.at(b).motor = on;
  belts_[b].reverse = reverse;
}

void World::set_speed(std::size_t b, double mps) {
  belts_.at(b).speed_mps = std::clamp(mps, 0.0, layout_.belts[b].max_speed_mps);
}

void World::set_exit(std::size_t b, std::size_t next_index) {
  belts_.at(b).exit = std::min(next_index, std::max<std::size_t>(layout_.belts[b].next.size(), 1) - 1);
}

void World::set_stopper(std::size_t b, std::size_t station, bool up) {
  belts_.at(b).stoppers.at(station) = up;
}

void World::set_jam(std::size_t b, bool jammed) {
  if (belts_.at(b).jammed == jammed) {
    return;
  }
  belts_[b].jammed = jammed;
  record(jammed ? EventKind::fault_raised : EventKind::fault_cleared, layout_.belts[b].name, 0, -1, {},
         "jam");
}

// --- boxes -----------------------------------------------------------------

Result<BoxId> World::place_box(std::size_t type, const StationRef& at, std::string_view by) {
  if (type >= layout_.catalog.box_types.size()) {
    return make_error(Errc::invalid_argument, fmt::format("box type {} is not in the catalog", type));
  }
  const double s = layout_.belts.at(at.belt).stations.at(at.station).at_m;
  const double half = layout_.catalog.box_types[type].size_m.x / 2.0;
  if (!span_free(at.belt, s, half, 0)) {
    return make_error(Errc::state, fmt::format("station {} is occupied", station_name(at.belt, at.station)));
  }
  Box box;
  box.id = next_box_++;
  box.type = type;
  box.slots.assign(static_cast<std::size_t>(layout_.catalog.box_types[type].capacity()), -1);
  box.belt = at.belt;
  box.s = s;
  box.station = static_cast<int>(at.station);
  box.moved_step = steps_;
  boxes_.push_back(std::move(box));
  reindex();
  ++counters_.uploaded;
  record(EventKind::box_uploaded, std::string(by), boxes_.back().id, -1, {},
         layout_.catalog.box_types[type].name);
  record(EventKind::box_entered_station, station_name(at.belt, at.station), boxes_.back().id);
  return boxes_.back().id;
}

Result<Inspection> World::take_box(const StationRef& at, std::string_view by) {
  const Box* in_place = box_in_place(at.belt, at.station);
  if (in_place == nullptr) {
    return make_error(Errc::state, fmt::format("no box in place at {}", station_name(at.belt, at.station)));
  }
  const auto it = boxes_.begin() + (in_place - boxes_.data());
  Inspection inspection;
  inspection.box = it->id;
  inspection.type = it->type;
  inspection.counts.assign(layout_.catalog.candy_types.size(), 0);
  inspection.weight_g = layout_.catalog.box_types[it->type].tare_g;
  for (int candy : it->slots) {
    if (candy >= 0) {
      ++inspection.counts[static_cast<std::size_t>(candy)];
      inspection.weight_g += layout_.catalog.candy_types[static_cast<std::size_t>(candy)].unit_weight_g;
    }
  }
  record(EventKind::box_left_station, station_name(at.belt, at.station), it->id);
  record(EventKind::box_downloaded, std::string(by), it->id);
  std::string counts = fmt::format("weight={:.1f}g", inspection.weight_g);
  for (std::size_t c = 0; c < inspection.counts.size(); ++c) {
    if (inspection.counts[c] > 0) {
      counts += fmt::format(" {}={}", layout_.catalog.candy_types[c].name, inspection.counts[c]);
    }
  }
  record(EventKind::box_inspected, std::string(by), it->id, -1, {}, counts);
  boxes_.erase(it);
  reindex();
  ++counters_.downloaded;
  return inspection;
}

Status World::drop_box(BoxId id) {
  auto it = std::find_if(boxes_.begin(), boxes_.end(), [&](const Box& b) { return b.id == id; });
  if (it == boxes_.end()) {
    return make_error(Errc::not_found, fmt::format("box {} is not on the line", id));
  }
  record(EventKind::box_lost, layout_.belts[it->belt].name, id, -1, {}, "fell off the belt");
  boxes_.erase(it);
  reindex();
  ++counters_.boxes_lost;
  return {};
}

const Box* World::box(BoxId id) const {
  auto it = std::find_if(boxes_.begin(), boxes_.end(), [&](const Box& b) { return b.id == id; });
  return it == boxes_.end() ? nullptr : &*it;
}

motion::Vec3 World::box_position(const Box& box) const {
  const BeltSpec& belt = layout_.belts[box.belt];
  const motion::Vec2 p = belt.point_at(box.s);
  return {p.x, p.y, belt.height_m};
}

double World::box_heading(const Box& box) const {
  return layout_.belts[box.belt].heading_at(box.s);
}

motion::Vec3 World::slot_position(const Box& box, int slot) const {
  const BoxType& type = layout_.catalog.box_types[box.type];
  const motion::Vec3 centre = box_position(box);
  const motion::Vec2 p = centre.xy() + motion::rotate(type.slot_offset(slot), box_heading(box));
  return {p.x, p.y, centre.z + type.size_m.z};
}

// --- dispensers and tools ----------------------------------------------------

void World::set_stock(std::size_t dispenser, int stock) {
  const int capacity = layout_.dispensers.at(dispenser).capacity;
  const int before = stock_[dispenser];
  stock_[dispenser] = std::clamp(stock, 0, capacity);
  if ((before == 0) != (stock_[dispenser] == 0)) {
    record(stock_[dispenser] == 0 ? EventKind::fault_raised : EventKind::fault_cleared,
           layout_.dispensers[dispenser].name, 0, -1, layout_.dispensers[dispenser].candy, "dispenser empty");
  }
}

void World::set_mixup(std::size_t dispenser, bool mixed_up) {
  if (mixed_up_.at(dispenser) == mixed_up) {
    return;
  }
  mixed_up_[dispenser] = mixed_up;
  const std::string& holds = layout_.catalog.candy_types[dispensed_candy(dispenser)].name;
  record(mixed_up ? EventKind::fault_raised : EventKind::fault_cleared, layout_.dispensers[dispenser].name, 0,
         -1, holds, mixed_up ? "mixup: holds " + holds : "mixup cleared");
}

std::size_t World::dispensed_candy(std::size_t dispenser) const {
  const std::size_t own = *layout_.catalog.candy_index(layout_.dispensers.at(dispenser).candy);
  return mixed_up_[dispenser] ? (own + 1) % layout_.catalog.candy_types.size() : own;
}

void World::set_tool(std::size_t robot, const motion::ToolPose& pose, std::vector<double> joints) {
  tools_.at(robot).pose = pose;
  tools_[robot].joints = std::move(joints);
}

// A servo motor's windings approach the ambient temperature plus the rise of their load (while
// the arm moves) plus the rise of lost cooling, with a thermal time constant of minutes.
void World::heat_drives(std::size_t robot, double dt, bool moving) {
  constexpr double kLoadRiseC = 30.0;
  constexpr double kNoCoolingRiseC = 60.0;
  constexpr double kThermalTauS = 300.0;
  Tool& tool = tools_.at(robot);
  const double target =
      kAmbientTemperatureC + (moving ? kLoadRiseC : 0.0) + (tool.cooling_failed ? kNoCoolingRiseC : 0.0);
  tool.drive_temperature_c += (target - tool.drive_temperature_c) * (1.0 - std::exp(-dt / kThermalTauS));
}

void World::set_cooling_failed(std::size_t robot, bool failed) {
  tools_.at(robot).cooling_failed = failed;
  record(failed ? EventKind::fault_raised : EventKind::fault_cleared, layout_.robots.at(robot).name, 0, -1,
         {}, failed ? "overheat: the drives' cooling failed" : "overheat cleared");
}

void World::set_gripper(std::size_t robot, bool closed) {
  Tool& tool = tools_.at(robot);
  if (tool.gripper == closed) {
    return;
  }
  tool.gripper = closed;
  if (closed) {
    pick(robot);
  } else {
    release(robot);
  }
}

void World::pick(std::size_t robot) {
  Tool& tool = tools_[robot];
  const std::string& name = layout_.robots[robot].name;
  if (tool.held >= 0) {
    return;  // already holding one: the vacuum cup is busy
  }
  const double tol = layout_.pick_tolerance_m;
  for (std::size_t d = 0; d < layout_.dispensers.size(); ++d) {
    const DispenserSpec& spec = layout_.dispensers[d];
    if (motion::norm(tool.pose.position.xy() - spec.at.xy()) > tol ||
        std::abs(tool.pose.position.z - spec.at.z) > tol) {
      continue;
    }
    if (stock_[d] == 0) {
      ++counters_.pick_missed;
      record(EventKind::pick_missed, name, 0, -1, spec.candy, spec.name + " is empty");
      return;
    }
    set_stock(d, stock_[d] - 1);
    tool.held = static_cast<int>(dispensed_candy(d));
    ++counters_.picked;
    record(EventKind::candy_picked, name, 0, -1,
           layout_.catalog.candy_types[static_cast<std::size_t>(tool.held)].name, spec.name);
    return;
  }
  ++counters_.pick_missed;
  record(EventKind::pick_missed, name, 0, -1, {},
         fmt::format("no dispenser under the tool at ({:.4f}, {:.4f}, {:.4f})", tool.pose.position.x,
                     tool.pose.position.y, tool.pose.position.z));
}

void World::release(std::size_t robot) {
  Tool& tool = tools_[robot];
  if (tool.held < 0) {
    return;
  }
  const int candy = tool.held;
  tool.held = -1;
  const std::string& name = layout_.robots[robot].name;
  const std::string& candy_name = layout_.catalog.candy_types[static_cast<std::size_t>(candy)].name;
  for (Box& box : boxes_) {
    for (int slot = 0; slot < static_cast<int>(box.slots.size()); ++slot) {
      const motion::Vec3 p = slot_position(box, slot);
      const double dz = tool.pose.position.z - p.z;
      if (motion::norm(tool.pose.position.xy() - p.xy()) > layout_.place_tolerance_m || dz < -kSlotDepth ||
          dz > kReleaseHeight) {
        continue;
      }
      auto& content = box.slots[static_cast<std::size_t>(slot)];
      if (content >= 0) {
        ++counters_.dropped;
        record(EventKind::candy_dropped, name, box.id, slot, candy_name, "slot already filled");
        return;
      }
      content = candy;
      ++counters_.placed;
      record(EventKind::candy_placed, name, box.id, slot, candy_name);
      return;
    }
  }
  ++counters_.dropped;
  record(EventKind::candy_dropped, name, 0, -1, candy_name,
         fmt::format("not over a box slot at ({:.4f}, {:.4f}, {:.4f})", tool.pose.position.x,
                     tool.pose.position.y, tool.pose.position.z));
}

}  // namespace sf::plant
