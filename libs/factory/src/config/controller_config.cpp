// The keys every controller configuration shares (controller_config.hpp).
#include "sf/factory/controller_config.hpp"

#include <fmt/format.h>

#include "sf/opcua/security/provisioning.hpp"

namespace sf::factory {

namespace {

using config::Node;

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
  for (auto [key, text] :
       {std::pair<std::string_view, std::string*>{"interface", &d.interface}, {"partition", &d.partition}}) {
    SF_TRY(n.read(key, *text));
    if (text->empty()) {
      return n.child(key)->error(fmt::format("{} must not be empty", key));
    }
  }
  SF_TRY(read_duration(n, "lease_ms", kDurationMs, d.lease));
  if (d.lease < std::chrono::milliseconds{50}) {
    return n.child("lease_ms")->error("a lease shorter than 50 ms would declare a busy controller dead");
  }
  return {};
}

// A file name as given, or relative to the configuration's folder.
std::string beside(const std::filesystem::path& base, const std::string& file) {
  return file.empty() || std::filesystem::path(file).is_absolute() || base.empty() ? file
                                                                                   : (base / file).string();
}

Status parse_opcua(const Node& n, ControllerSettings& s, const std::filesystem::path& base) {
  SF_TRY(n.only_keys({"port", "host", "modes", "policies", "users", "anonymous", "pki", "nodesets"}));
  SF_TRY(n.read("port", s.opcua_port));
  SF_TRY(n.read("host", s.opcua_host));
  auto& sec = s.opcua_security;
  for (auto [key, text] : {std::pair<std::string_view, std::string*>{"modes", &sec.modes},
                           {"policies", &sec.policies},
                           {"users", &sec.users},
                           {"anonymous", &sec.anonymous},
                           {"pki", &sec.pki}}) {
    SF_TRY(n.read(key, *text));
  }
  if (auto modes = opcua::security::parse_security_modes(sec.modes); !modes) {
    return n.child("modes")->error(modes.error().message);
  }
  if (auto policies = opcua::security::parse_security_policies(sec.policies); !policies) {
    return n.child("policies")->error(policies.error().message);
  }
  sec.users = beside(base, sec.users);
  sec.pki = beside(base, sec.pki);
  SF_TRY(n.read("nodesets", s.opcua_nodesets));
  for (auto& file : s.opcua_nodesets) {
    file = beside(base, file);
  }
  return {};
}

}  // namespace

negotiation::DdsSettings dds_settings(const DdsOptions& o) {
  return negotiation::dds_settings(o.machining_domain, o.conveying_domain, o.partition, o.interface, o.lease);
}

Status read_duration(const Node& n, std::string_view key, double unit_ms, std::chrono::milliseconds& out) {
  double value = static_cast<double>(out.count()) / unit_ms;
  SF_TRY(n.read(key, value));
  if (!(value * unit_ms >= 1.0) || value * unit_ms > 1e9) {
    return n.child(key)->error("must be a duration of 1 ms up to 11 days");
  }
  out = std::chrono::milliseconds(static_cast<std::int64_t>(value * unit_ms));
  return {};
}

Status parse_controller_settings(const Node& root, ControllerSettings& s, const std::filesystem::path& base) {
  // A controller stands for a machine of the layout; the order service names itself.
  if (s.machine.empty()) {
    auto machine = root.get<std::string>("machine");
    if (!machine) {
      return machine.error();
    }
    s.machine = *machine;
  }
  std::string layout;
  SF_TRY(root.read("layout", layout));
  s.layout_file = layout;
  SF_TRY(root.read("serial_number", s.serial_number));
  std::string start = "stopped";
  SF_TRY(root.read("start", start));
  if (start != "stopped" && start != "execute") {
    return root.child("start")->error(fmt::format("start is stopped or execute, not '{}'", start));
  }
  s.auto_start = start == "execute";
  SF_TRY(read_duration(root, "job_timeout_s", kDurationSeconds, s.job_timeout));
  if (root.has("opcua")) {
    SF_TRY(parse_opcua(*root.child("opcua"), s, base));
  }
  if (root.has("dds")) {
    SF_TRY(parse_dds(*root.child("dds"), s.dds));
  }
  return {};
}

Result<line::Layout> load_settings_layout(const Node& root, const ControllerSettings& s,
                                          const std::filesystem::path& base) {
  const auto& file = s.layout_file;
  auto layout =
      file.empty() ? line::default_layout() : line::load_layout(file.is_absolute() ? file : base / file);
  if (!layout) {
    return root.has("layout") ? root.child("layout")->error(layout.error().message) : layout.error();
  }
  return layout;
}

}  // namespace sf::factory
