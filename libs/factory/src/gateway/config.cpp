// Reading a gateway configuration (gateway_config.hpp): the YAML shape key by
// key, then the checks against the layout it names.
#include <fmt/format.h>

#include "sf/core/config.hpp"
#include "sf/factory/gateway_config.hpp"

namespace sf::factory {

namespace {

using config::Node;

constexpr GatewayKind kKinds[] = {GatewayKind::conveyor, GatewayKind::uploader, GatewayKind::downloader,
                                  GatewayKind::legacy_robot};

Status parse_modbus(const Node& n, ModbusEndpoint& m) {
  SF_TRY(n.only_keys({"host", "port", "unit_id", "timeout_ms", "poll_period_ms", "stale_after_ms"}));
  SF_TRY(n.read("host", m.host));
  if (m.host.empty()) {
    return n.child("host")->error("a host is needed");
  }
  SF_TRY(n.read("port", m.port));
  SF_TRY(n.read("unit_id", m.unit_id));
  SF_TRY(read_duration(n, "timeout_ms", kDurationMs, m.timeout));
  SF_TRY(read_duration(n, "poll_period_ms", kDurationMs, m.poll_period));
  SF_TRY(read_duration(n, "stale_after_ms", kDurationMs, m.stale_after));
  return {};
}

Status parse_robot(const Node& n, RobotProgram& r) {
  SF_TRY(n.only_keys({"station", "approach_m", "release_above_m", "home_above_m", "grip_s"}));
  SF_TRY(n.read("station", r.station));
  for (auto [key, value] : {std::pair<std::string_view, double*>{"approach_m", &r.approach_m},
                            {"release_above_m", &r.release_above_m},
                            {"home_above_m", &r.home_above_m}}) {
    SF_TRY(n.read(key, *value));
    if (*value < 0.0 || *value > 2.0) {
      return n.child(key)->error("expected 0..2 m");
    }
  }
  return read_duration(n, "grip_s", kDurationSeconds, r.grip);
}

Result<GatewayKind> parse_kind(const Node& n) {
  auto text = n.as<std::string>();
  if (!text) {
    return text.error();
  }
  for (GatewayKind k : kKinds) {
    if (*text == to_string(k)) {
      return k;
    }
  }
  return n.error(
      fmt::format("unknown kind '{}' (known: conveyor, uploader, downloader, legacy-robot)", *text));
}

Status parse_root(const Node& root, GatewayConfig& c, const std::filesystem::path& base) {
  SF_TRY(root.only_keys({"machine", "kind", "layout", "serial_number", "start", "job_timeout_s", "modbus",
                         "opcua", "dds", "robot"}));
  SF_TRY(parse_controller_settings(root, c.controller, base));
  auto kind_node = root.child("kind");
  if (!kind_node) {
    return kind_node.error();
  }
  auto kind = parse_kind(*kind_node);
  if (!kind) {
    return kind.error();
  }
  c.kind = *kind;
  if (root.has("modbus")) {
    SF_TRY(parse_modbus(*root.child("modbus"), c.modbus));
  }
  if (root.has("robot")) {
    if (c.kind != GatewayKind::legacy_robot) {
      return root.child("robot")->error("robot settings belong to a legacy-robot gateway");
    }
    SF_TRY(parse_robot(*root.child("robot"), c.robot));
  }
  return {};
}

// The machine of the layout the configuration stands for, as its kind.
Status check_machine(const Node& root, const GatewayConfig& c, const line::Layout& layout) {
  const Node at = *root.child("machine");
  switch (c.kind) {
    case GatewayKind::conveyor:
      if (layout.belt(c.controller.machine) == nullptr) {
        return at.error(fmt::format("the layout has no belt '{}'", c.controller.machine));
      }
      return {};
    case GatewayKind::uploader:
    case GatewayKind::downloader: {
      const auto& spec = c.kind == GatewayKind::uploader ? layout.uploader : layout.downloader;
      if (spec.name != c.controller.machine) {
        return at.error(fmt::format("the layout's {} is '{}', not '{}'", to_string(c.kind), spec.name,
                                    c.controller.machine));
      }
      return {};
    }
    case GatewayKind::legacy_robot: {
      const line::RobotSpec* robot = layout.robot(c.controller.machine);
      if (robot == nullptr) {
        return at.error(fmt::format("the layout has no robot '{}'", c.controller.machine));
      }
      if (!robot->legacy()) {
        return at.error(fmt::format("'{}' is a {} robot with its own controller, not a legacy one",
                                    c.controller.machine, line::to_string(robot->kind)));
      }
      return {};
    }
  }
  return {};
}

Status check_station(const Node& root, const GatewayConfig& c, const line::Layout& layout) {
  if (c.kind != GatewayKind::legacy_robot || c.robot.station.empty()) {
    return {};
  }
  const auto& stations = layout.robot(c.controller.machine)->stations;
  if (std::find(stations.begin(), stations.end(), c.robot.station) == stations.end()) {
    return root.child("robot")->child("station")->error(
        fmt::format("'{}' is not one of {}'s stations", c.robot.station, c.controller.machine));
  }
  return {};
}

Result<GatewaySetup> parse_gateway(const Node& root, const std::filesystem::path& base) {
  GatewaySetup setup;
  SF_TRY(parse_root(root, setup.config, base));
  auto layout = load_settings_layout(root, setup.config.controller, base);
  if (!layout) {
    return layout.error();
  }
  setup.layout = std::move(*layout);
  SF_TRY(check_machine(root, setup.config, setup.layout));
  SF_TRY(check_station(root, setup.config, setup.layout));
  return setup;
}

}  // namespace

std::string_view to_string(GatewayKind kind) {
  switch (kind) {
    case GatewayKind::conveyor:
      return "conveyor";
    case GatewayKind::uploader:
      return "uploader";
    case GatewayKind::downloader:
      return "downloader";
    case GatewayKind::legacy_robot:
      return "legacy-robot";
  }
  return "?";
}

Result<GatewaySetup> load_gateway_config(const std::filesystem::path& file) {
  auto root = config::load_file(file);
  if (!root) {
    return root.error();
  }
  return parse_gateway(*root, file.parent_path());
}

Result<GatewaySetup> parse_gateway_config(std::string_view yaml, std::string name,
                                          const std::filesystem::path& base) {
  auto root = config::load_string(yaml, std::move(name));
  if (!root) {
    return root.error();
  }
  return parse_gateway(*root, base);
}

}  // namespace sf::factory
