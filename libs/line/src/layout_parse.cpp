// Reading a layout file (layout.hpp): the YAML shape, key by key. The
// checks that need the whole layout (names, geometry, reach) are in
// layout_check.cpp.
#include <fmt/format.h>

#include "layout_check.hpp"
#include "sf/core/config.hpp"
#include "sf/line/layout.hpp"

namespace sf::line {

namespace {

using config::Node;

Result<std::vector<double>> numbers(const Node& node, std::size_t count) {
  auto items = node.items();
  if (!items) {
    return items.error();
  }
  if (items->size() != count) {
    return node.error(fmt::format("expected a list of {} numbers", count));
  }
  std::vector<double> out;
  for (const auto& item : *items) {
    auto v = item.as<double>();
    if (!v) {
      return v.error();
    }
    out.push_back(*v);
  }
  return out;
}

Result<Vec2> vec2(const Node& node) {
  auto v = numbers(node, 2);
  if (!v) {
    return v.error();
  }
  return Vec2{(*v)[0], (*v)[1]};
}

Result<Vec3> vec3(const Node& node) {
  auto v = numbers(node, 3);
  if (!v) {
    return v.error();
  }
  return Vec3{(*v)[0], (*v)[1], (*v)[2]};
}

Status read_vec3(const Node& node, std::string_view key, Vec3& out) {
  auto c = node.child(key);
  if (!c) {
    return c.error();
  }
  auto v = vec3(*c);
  if (!v) {
    return v.error();
  }
  out = *v;
  return {};
}

// Each element of the list at `key`, parsed by `parse`.
template <typename T, typename F>
Result<std::vector<T>> list(const Node& node, std::string_view key, F parse) {
  std::vector<T> out;
  if (!node.has(key)) {
    return out;
  }
  auto c = node.child(key);
  if (!c) {
    return c.error();
  }
  auto items = c->items();
  if (!items) {
    return items.error();
  }
  for (const auto& item : *items) {
    T value;
    value.where = item.where() + ": " + item.path();
    SF_TRY(parse(item, value));
    out.push_back(std::move(value));
  }
  return out;
}

// The required `name` and the optional `label` (the name when missing) of an entry.
template <typename T>
Status read_name(const Node& n, T& item) {
  auto name = n.get<std::string>("name");
  if (!name) {
    return name.error();
  }
  item.name = *name;
  item.label = item.name;
  return n.read("label", item.label);
}

Status parse_candy(const Node& n, CandyType& c) {
  SF_TRY(n.only_keys({"name", "label", "unit_weight_g"}));
  SF_TRY(read_name(n, c));
  return n.read("unit_weight_g", c.unit_weight_g);
}

Status parse_box(const Node& n, BoxType& b) {
  SF_TRY(n.only_keys({"name", "label", "rows", "columns", "pitch_m", "size_m", "tare_g"}));
  SF_TRY(read_name(n, b));
  SF_TRY(n.read("rows", b.rows));
  SF_TRY(n.read("columns", b.columns));
  SF_TRY(n.read("pitch_m", b.pitch_m));
  SF_TRY(read_vec3(n, "size_m", b.size_m));
  return n.read("tare_g", b.tare_g);
}

Status parse_plc(const Node& parent, PlcSpec& plc) {
  if (!parent.has("plc")) {
    return {};
  }
  auto n = parent.child("plc");
  if (!n) {
    return n.error();
  }
  SF_TRY(n->only_keys({"vendor", "model", "port"}));
  SF_TRY(n->read("vendor", plc.vendor));
  SF_TRY(n->read("model", plc.model));
  return n->read("port", plc.port);
}

Status parse_station(const Node& n, StationSpec& s) {
  SF_TRY(n.only_keys({"name", "at_m"}));
  auto name = n.get<std::string>("name");
  auto at = n.get<double>("at_m");
  if (!name) {
    return name.error();
  }
  if (!at) {
    return at.error();
  }
  s.name = *name;
  s.at_m = *at;
  return {};
}

Status parse_belt(const Node& n, BeltSpec& b) {
  SF_TRY(n.only_keys({"name", "label", "plc", "path", "height_m", "speed_mps", "max_speed_mps", "next",
                      "stations", "capabilities"}));
  SF_TRY(read_name(n, b));
  SF_TRY(parse_plc(n, b.plc));
  auto path = n.child("path");
  if (!path) {
    return path.error();
  }
  auto points = path->items();
  if (!points) {
    return points.error();
  }
  for (const auto& p : *points) {
    auto v = vec2(p);
    if (!v) {
      return v.error();
    }
    b.path.push_back(*v);
  }
  SF_TRY(n.read("height_m", b.height_m));
  SF_TRY(n.read("speed_mps", b.speed_mps));
  SF_TRY(n.read("max_speed_mps", b.max_speed_mps));
  SF_TRY(n.read("next", b.next));
  SF_TRY(n.read("capabilities", b.capabilities));
  auto stations = list<StationSpec>(n, "stations", parse_station);
  if (!stations) {
    return stations.error();
  }
  b.stations = std::move(*stations);
  return {};
}

Status parse_dispenser(const Node& n, DispenserSpec& d) {
  SF_TRY(n.only_keys({"name", "candy", "at", "stock", "capacity"}));
  auto name = n.get<std::string>("name");
  auto candy = n.get<std::string>("candy");
  if (!name) {
    return name.error();
  }
  if (!candy) {
    return candy.error();
  }
  d.name = *name;
  d.candy = *candy;
  SF_TRY(read_vec3(n, "at", d.at));
  SF_TRY(n.read("stock", d.stock));
  d.capacity = d.stock;
  return n.read("capacity", d.capacity);
}

Result<RobotKind> robot_kind(const Node& n) {
  auto kind = n.get<std::string>("kind");
  if (!kind) {
    return kind.error();
  }
  for (auto k : {RobotKind::smart_scara, RobotKind::legacy_scara, RobotKind::legacy_articulated}) {
    if (*kind == to_string(k)) {
      return k;
    }
  }
  auto c = n.child("kind");
  return c->error(
      fmt::format("unknown robot kind '{}' (known: smart-scara, legacy-scara, legacy-articulated)", *kind));
}

// links_m: [l1, l2] for a SCARA; [shoulder height, upper arm, forearm, tool] for an articulated arm.
Status parse_arm(const Node& n, RobotSpec& r) {
  Vec3 base;
  SF_TRY(read_vec3(n, "base", base));
  auto links = n.child("links_m");
  if (!links) {
    return links.error();
  }
  if (r.kind == RobotKind::legacy_articulated) {
    auto v = numbers(*links, 4);
    if (!v) {
      return v.error();
    }
    r.articulated.base = base;
    r.articulated.shoulder = (*v)[0];
    r.articulated.upper = (*v)[1];
    r.articulated.fore = (*v)[2];
    r.articulated.tool = (*v)[3];
    return {};
  }
  auto v = numbers(*links, 2);
  if (!v) {
    return v.error();
  }
  r.scara.base = base;
  r.scara.l1 = (*v)[0];
  r.scara.l2 = (*v)[1];
  double stroke = r.scara.limits[2].max;
  SF_TRY(n.read("z_stroke_m", stroke));
  r.scara.limits[2] = {0.0, stroke};
  return {};
}

Status parse_robot(const Node& n, RobotSpec& r) {
  SF_TRY(n.only_keys({"name", "label", "kind", "vendor", "model", "base", "links_m", "z_stroke_m",
                      "tool_speed_mps", "controller", "stations", "dispensers", "capabilities", "home"}));
  SF_TRY(read_name(n, r));
  auto kind = robot_kind(n);
  if (!kind) {
    return kind.error();
  }
  r.kind = *kind;
  SF_TRY(n.read("vendor", r.vendor));
  SF_TRY(n.read("model", r.model));
  SF_TRY(parse_arm(n, r));
  if (r.kind == RobotKind::legacy_articulated && n.has("z_stroke_m")) {
    return n.child("z_stroke_m")->error("an articulated arm has no z stroke");
  }
  SF_TRY(n.read("tool_speed_mps", r.tool_speed_mps));
  if (n.has("controller")) {
    auto c = n.child("controller");
    SF_TRY(c->only_keys({"vendor", "model", "port"}));
    SF_TRY(c->read("vendor", r.controller.vendor));
    SF_TRY(c->read("model", r.controller.model));
    SF_TRY(c->read("port", r.controller.port));
  }
  if (r.controller.vendor.empty()) {
    r.controller.vendor = r.vendor;
  }
  SF_TRY(n.read("stations", r.stations));
  SF_TRY(n.read("capabilities", r.capabilities));
  if (n.has("home")) {
    Vec3 home;
    SF_TRY(read_vec3(n, "home", home));
    r.home = home;
  }
  return n.read("dispensers", r.dispensers);
}

Status parse_transfer(const Node& root, std::string_view key, TransferSpec& t) {
  auto n = root.child(key);
  if (!n) {
    return n.error();
  }
  t.where = n->where() + ": " + n->path();
  SF_TRY(n->only_keys({"name", "label", "plc", "station", "cycle_s", "capabilities"}));
  t.capabilities = {key == "uploader" ? "box-loading" : "box-unloading"};
  SF_TRY(n->read("capabilities", t.capabilities));
  t.name = std::string(key);
  SF_TRY(n->read("name", t.name));
  t.label = t.name;
  SF_TRY(n->read("label", t.label));
  SF_TRY(parse_plc(*n, t.plc));
  auto station = n->get<std::string>("station");
  if (!station) {
    return station.error();
  }
  t.station = *station;
  return n->read("cycle_s", t.cycle_s);
}

Status parse_catalog(const Node& root, Catalog& catalog) {
  auto n = root.child("catalog");
  if (!n) {
    return n.error();
  }
  SF_TRY(n->only_keys({"candy_types", "box_types"}));
  auto candies = list<CandyType>(*n, "candy_types", parse_candy);
  if (!candies) {
    return candies.error();
  }
  auto boxes = list<BoxType>(*n, "box_types", parse_box);
  if (!boxes) {
    return boxes.error();
  }
  catalog.candy_types = std::move(*candies);
  catalog.box_types = std::move(*boxes);
  if (catalog.candy_types.empty() || catalog.box_types.empty()) {
    return n->error("the catalog needs at least one candy type and one box type");
  }
  return {};
}

Result<Layout> parse(const Node& root) {
  SF_TRY(root.only_keys({"line", "label", "catalog", "belts", "dispensers", "robots", "uploader",
                         "downloader", "pick_tolerance_m", "place_tolerance_m"}));
  Layout layout;
  layout.source = root.file();
  auto line = root.get<std::string>("line");
  if (!line) {
    return line.error();
  }
  layout.line = *line;
  layout.label = layout.line;
  SF_TRY(root.read("label", layout.label));
  SF_TRY(parse_catalog(root, layout.catalog));
  auto belts = list<BeltSpec>(root, "belts", parse_belt);
  if (!belts) {
    return belts.error();
  }
  layout.belts = std::move(*belts);
  auto dispensers = list<DispenserSpec>(root, "dispensers", parse_dispenser);
  if (!dispensers) {
    return dispensers.error();
  }
  layout.dispensers = std::move(*dispensers);
  auto robots = list<RobotSpec>(root, "robots", parse_robot);
  if (!robots) {
    return robots.error();
  }
  layout.robots = std::move(*robots);
  SF_TRY(parse_transfer(root, "uploader", layout.uploader));
  SF_TRY(parse_transfer(root, "downloader", layout.downloader));
  SF_TRY(root.read("pick_tolerance_m", layout.pick_tolerance_m));
  SF_TRY(root.read("place_tolerance_m", layout.place_tolerance_m));
  SF_TRY(check_layout(layout));
  return layout;
}

}  // namespace

Result<Layout> parse_layout(std::string_view yaml, std::string name) {
  auto root = config::load_string(yaml, std::move(name));
  if (!root) {
    return root.error();
  }
  return parse(*root);
}

Result<Layout> load_layout(const std::filesystem::path& file) {
  auto root = config::load_file(file);
  if (!root) {
    return root.error();
  }
  return parse(*root);
}

Result<Layout> default_layout() {
  return parse_layout(default_layout_yaml(), "layouts/prototype-line.yaml");
}

}  // namespace sf::line
