#include "sf/plant/snapshot.hpp"

#include <nlohmann/json.hpp>

namespace sf::plant {

namespace {

using nlohmann::json;

json vec(const motion::Vec3& v) {
  return json::array({v.x, v.y, v.z});
}

BoxView view(const World& world, const Box& box) {
  const Layout& l = world.layout();
  BoxView v;
  v.id = box.id;
  v.type = l.catalog.box_types[box.type].name;
  v.belt = l.belts[box.belt].name;
  v.s = box.s;
  v.position = world.box_position(box);
  v.heading = world.box_heading(box);
  if (box.station >= 0) {
    v.station = v.belt + "/" + l.belts[box.belt].stations[static_cast<std::size_t>(box.station)].name;
  }
  for (int candy : box.slots) {
    v.slots.push_back(candy < 0 ? "" : l.catalog.candy_types[static_cast<std::size_t>(candy)].name);
  }
  return v;
}

}  // namespace

Snapshot world_snapshot(const World& world) {
  const Layout& l = world.layout();
  Snapshot s;
  s.time = world.time();
  for (const Box& box : world.boxes()) {
    s.boxes.push_back(view(world, box));
  }
  for (std::size_t b = 0; b < l.belts.size(); ++b) {
    const BeltState& state = world.belt(b);
    BeltView v{l.belts[b].name, state.motor,        state.reverse,     state.speed_mps, "",
               state.jammed,    world.entry_eye(b), world.exit_eye(b), state.stoppers,  {}};
    if (!l.belts[b].next.empty()) {
      v.exit = l.belts[b].next[std::min(state.exit, l.belts[b].next.size() - 1)];
    }
    for (std::size_t k = 0; k < l.belts[b].stations.size(); ++k) {
      v.station_eyes.push_back(world.station_eye(b, k));
    }
    s.belts.push_back(std::move(v));
  }
  for (std::size_t d = 0; d < l.dispensers.size(); ++d) {
    s.dispensers.push_back({l.dispensers[d].name, l.dispensers[d].candy, world.stock(d)});
  }
  for (std::size_t r = 0; r < l.robots.size(); ++r) {
    const Tool& tool = world.tool(r);
    s.robots.push_back(
        {l.robots[r].name, std::string(to_string(l.robots[r].kind)), tool.pose, tool.joints, tool.gripper,
         tool.held < 0 ? "" : l.catalog.candy_types[static_cast<std::size_t>(tool.held)].name});
  }
  s.counters = world.counters();
  s.events = world.events().total();
  return s;
}

json to_json(const Event& e) {
  json j{{"t", std::chrono::duration<double>(e.at).count()}, {"kind", to_string(e.kind)}, {"where", e.where}};
  if (e.box != 0) {
    j["box"] = e.box;
  }
  if (e.slot >= 0) {
    j["slot"] = e.slot;
  }
  if (!e.candy.empty()) {
    j["candy"] = e.candy;
  }
  if (!e.detail.empty()) {
    j["detail"] = e.detail;
  }
  return j;
}

json to_json(const Snapshot& s) {
  json boxes = json::array();
  for (const auto& b : s.boxes) {
    boxes.push_back({{"id", b.id},
                     {"type", b.type},
                     {"belt", b.belt},
                     {"s", b.s},
                     {"position", vec(b.position)},
                     {"heading", b.heading},
                     {"station", b.station},
                     {"slots", b.slots}});
  }
  json belts = json::array();
  for (const auto& b : s.belts) {
    belts.push_back({{"name", b.name},
                     {"motor", b.motor},
                     {"reverse", b.reverse},
                     {"speed_mps", b.speed_mps},
                     {"exit", b.exit},
                     {"jammed", b.jammed},
                     {"entry_eye", b.entry_eye},
                     {"exit_eye", b.exit_eye},
                     {"stoppers", b.stoppers},
                     {"station_eyes", b.station_eyes}});
  }
  json dispensers = json::array();
  for (const auto& d : s.dispensers) {
    dispensers.push_back({{"name", d.name}, {"candy", d.candy}, {"stock", d.stock}});
  }
  json robots = json::array();
  for (const auto& r : s.robots) {
    robots.push_back({{"name", r.name},
                      {"kind", r.kind},
                      {"tool", vec(r.tool.position)},
                      {"yaw", r.tool.yaw},
                      {"joints", r.joints},
                      {"gripper", r.gripper},
                      {"held", r.held}});
  }
  json machines = json::array();
  for (const auto& m : s.machines) {
    machines.push_back(
        {{"name", m.name}, {"kind", m.kind}, {"fault_code", m.fault_code}, {"fault", m.fault}});
  }
  const auto& c = s.counters;
  return {{"time", std::chrono::duration<double>(s.time).count()},
          {"boxes", boxes},
          {"belts", belts},
          {"dispensers", dispensers},
          {"robots", robots},
          {"machines", machines},
          {"faults", s.faults},
          {"counters",
           {{"uploaded", c.uploaded},
            {"downloaded", c.downloaded},
            {"picked", c.picked},
            {"placed", c.placed},
            {"dropped", c.dropped},
            {"pick_missed", c.pick_missed},
            {"boxes_lost", c.boxes_lost}}},
          {"events", s.events}};
}

}  // namespace sf::plant
