// Reading the smart robot's IPC configuration (machine_config.hpp).
#include "sf/factory/machine_config.hpp"

#include <fmt/format.h>

namespace sf::factory {

namespace {

using config::Node;

Status parse_ethercat(const Node& n, EtherCatOptions& e) {
  SF_TRY(n.only_keys({"link", "cycle_us", "slave", "realtime"}));
  SF_TRY(n.read("link", e.link));
  if (e.link.empty()) {
    return n.child("link")->error("a link is needed: udp:HOST:PORT or an interface name");
  }
  auto cycle = static_cast<std::int64_t>(e.cycle.count());
  SF_TRY(n.read("cycle_us", cycle));
  if (cycle < 125 || cycle > 100'000) {
    return n.child("cycle_us")->error("the cycle is 125 µs .. 100 ms");
  }
  e.cycle = std::chrono::microseconds(cycle);
  SF_TRY(n.read("slave", e.slave));
  return n.read("realtime", e.realtime);
}

Status parse_pick_place(const Node& n, PickPlace& p) {
  SF_TRY(n.only_keys({"approach_m", "release_m", "blend_m", "grip_timeout_ms", "release_timeout_ms"}));
  for (auto [key, value] : {std::pair<std::string_view, double*>{"approach_m", &p.approach_m},
                            {"release_m", &p.release_m},
                            {"blend_m", &p.blend_m}}) {
    SF_TRY(n.read(key, *value));
    if (!(*value >= 0.0 && *value <= 0.5)) {
      return n.child(key)->error("expected 0..0.5 m");
    }
  }
  SF_TRY(read_duration(n, "grip_timeout_ms", 1.0, p.grip_timeout));
  return read_duration(n, "release_timeout_ms", 1.0, p.release_timeout);
}

Result<MachineSetup> parse_machine(const Node& root, const std::filesystem::path& base) {
  SF_TRY(root.only_keys({"machine", "layout", "serial_number", "start", "job_timeout_s", "opcua", "dds",
                         "ethercat", "pick_place"}));
  MachineSetup setup;
  MachineConfig& c = setup.config;
  SF_TRY(parse_controller_settings(root, c.controller, base));
  if (root.has("ethercat")) {
    SF_TRY(parse_ethercat(*root.child("ethercat"), c.ethercat));
  }
  if (root.has("pick_place")) {
    SF_TRY(parse_pick_place(*root.child("pick_place"), c.pick_place));
  }
  auto layout = load_settings_layout(root, c.controller, base);
  if (!layout) {
    return layout.error();
  }
  setup.layout = std::move(*layout);
  const line::RobotSpec* robot = setup.layout.robot(c.controller.machine);
  if (robot == nullptr || robot->legacy()) {
    return root.child("machine")->error(
        robot == nullptr
            ? fmt::format("the layout has no robot '{}'", c.controller.machine)
            : fmt::format("'{}' is a legacy robot: its gateway drives it, not a machine controller",
                          c.controller.machine));
  }
  return setup;
}

}  // namespace

Result<MachineSetup> load_machine_config(const std::filesystem::path& file) {
  auto root = config::load_file(file);
  if (!root) {
    return root.error();
  }
  return parse_machine(*root, file.parent_path());
}

Result<MachineSetup> parse_machine_config(std::string_view yaml, std::string name,
                                          const std::filesystem::path& base) {
  auto root = config::load_string(yaml, std::move(name));
  if (!root) {
    return root.error();
  }
  return parse_machine(*root, base);
}

SmartRobotConfig smart_robot_config(const MachineConfig& config) {
  SmartRobotConfig r;
  r.robot = config.controller.machine;
  r.serial_number = config.controller.serial_number;
  r.slave = config.ethercat.slave;
  r.limits.cycle = std::chrono::duration<double>(config.ethercat.cycle).count();
  r.pick_place = config.pick_place;
  r.auto_start = config.controller.auto_start;
  r.job_timeout = config.controller.job_timeout;
  return r;
}

}  // namespace sf::factory
