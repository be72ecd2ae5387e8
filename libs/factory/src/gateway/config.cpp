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

constexpr double kMs = 1.0;
constexpr double kSeconds = 1000.0;

// A duration key, in units of `unit_ms` milliseconds, that must be positive.
Status read_duration(const Node& n, std::string_view key, double unit_ms, std::chrono::milliseconds& out) {
  double value = static_cast<double>(out.count()) / unit_ms;
  SF_TRY(n.read(key, value));
  if (!(value * unit_ms >= 1.0) || value * unit_ms > 1e9) {
    return n.child(key)->error("must be a duration of 1 ms up to 11 days");
  }
  out = std::chrono::milliseconds(static_cast<std::int64_t>(value * unit_ms));
  return {};
}

Status parse_modbus(const Node& n, ModbusEndpoint& m) {
  SF_TRY(n.only_keys({"host", "port", "unit_id", "timeout_ms", "poll_period_ms", "stale_after_ms"}));
  SF_TRY(n.read("host", m.host));
  if (m.host.empty()) {
    return n.child("host")->error("a host is needed");
  }
  SF_TRY(n.read("port", m.port));
  SF_TRY(n.read("unit_id", m.unit_id));
  SF_TRY(read_duration(n, "timeout_ms", kMs, m.timeout));
  SF_TRY(read_duration(n, "poll_period_ms", kMs, m.poll_period));
  SF_TRY(read_duration(n, "stale_after_ms", kMs, m.stale_after));
  return {};
}

Status parse_dds(const Node& n, DdsOptions& d) {
  SF_TRY(n.only_keys({"machining_domain", "conveying_domain", "interface", "partition", "lease_ms"}));
  for (auto [key, domain] :
       {std::pair<std::string_view, std::uint32_t*>{"machining_domain", &d.machining_domain},
        {"conveying_domain", &d.conveying_domain}}) {
    SF_TRY(n.read(key, *domain));
    if (*domain > 232) {  // DDSI-RTPS 2.5 §9.6.1.1: the port arithmetic leaves 0..232
      return n.child(key)->error("a DDS domain id is 0..232");
    }
  }
  SF_TRY(n.read("interface", d.interface));
  SF_TRY(n.read("partition", d.partition));
  for (auto [key, text] :
       {std::pair<std::string_view, std::string*>{"interface", &d.interface}, {"partition", &d.partition}}) {
    if (text->empty()) {
      return n.child(key)->error(fmt::format("{} must not be empty", key));
    }
  }
  SF_TRY(read_duration(n, "lease_ms", kMs, d.lease));
  if (d.lease < std::chrono::milliseconds{50}) {
    return n.child("lease_ms")->error("a lease shorter than 50 ms would declare a busy gateway dead");
  }
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
  return read_duration(n, "grip_s", kSeconds, r.grip);
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

Status parse_root(const Node& root, GatewayConfig& c) {
  SF_TRY(root.only_keys({"machine", "kind", "layout", "serial_number", "start", "job_timeout_s", "modbus",
                         "opcua", "dds", "robot"}));
  auto machine = root.get<std::string>("machine");
  if (!machine) {
    return machine.error();
  }
  c.machine = *machine;
  auto kind_node = root.child("kind");
  if (!kind_node) {
    return kind_node.error();
  }
  auto kind = parse_kind(*kind_node);
  if (!kind) {
    return kind.error();
  }
  c.kind = *kind;
  std::string layout;
  SF_TRY(root.read("layout", layout));
  c.layout_file = layout;
  SF_TRY(root.read("serial_number", c.serial_number));
  std::string start = "stopped";
  SF_TRY(root.read("start", start));
  if (start != "stopped" && start != "execute") {
    return root.child("start")->error(fmt::format("start is stopped or execute, not '{}'", start));
  }
  c.auto_start = start == "execute";
  SF_TRY(read_duration(root, "job_timeout_s", kSeconds, c.job_timeout));
  if (root.has("modbus")) {
    SF_TRY(parse_modbus(*root.child("modbus"), c.modbus));
  }
  if (root.has("opcua")) {
    auto opcua = root.child("opcua");
    SF_TRY(opcua->only_keys({"port"}));
    SF_TRY(opcua->read("port", c.opcua_port));
  }
  if (root.has("dds")) {
    SF_TRY(parse_dds(*root.child("dds"), c.dds));
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
      if (layout.belt(c.machine) == nullptr) {
        return at.error(fmt::format("the layout has no belt '{}'", c.machine));
      }
      return {};
    case GatewayKind::uploader:
    case GatewayKind::downloader: {
      const auto& spec = c.kind == GatewayKind::uploader ? layout.uploader : layout.downloader;
      if (spec.name != c.machine) {
        return at.error(
            fmt::format("the layout's {} is '{}', not '{}'", to_string(c.kind), spec.name, c.machine));
      }
      return {};
    }
    case GatewayKind::legacy_robot: {
      const line::RobotSpec* robot = layout.robot(c.machine);
      if (robot == nullptr) {
        return at.error(fmt::format("the layout has no robot '{}'", c.machine));
      }
      if (!robot->legacy()) {
        return at.error(fmt::format("'{}' is a {} robot with its own controller, not a legacy one", c.machine,
                                    line::to_string(robot->kind)));
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
  const auto& stations = layout.robot(c.machine)->stations;
  if (std::find(stations.begin(), stations.end(), c.robot.station) == stations.end()) {
    return root.child("robot")->child("station")->error(
        fmt::format("'{}' is not one of {}'s stations", c.robot.station, c.machine));
  }
  return {};
}

Result<GatewaySetup> parse(const Node& root, const std::filesystem::path& base) {
  GatewaySetup setup;
  SF_TRY(parse_root(root, setup.config));
  const auto& file = setup.config.layout_file;
  auto layout =
      file.empty() ? line::default_layout() : line::load_layout(file.is_absolute() ? file : base / file);
  if (!layout) {
    return root.child("layout")->error(layout.error().message);
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
  return parse(*root, file.parent_path());
}

Result<GatewaySetup> parse_gateway_config(std::string_view yaml, std::string name,
                                          const std::filesystem::path& base) {
  auto root = config::load_string(yaml, std::move(name));
  if (!root) {
    return root.error();
  }
  return parse(*root, base);
}

}  // namespace sf::factory
