// What the tests of the line's plan share: options for a plan of the default layout and the
// endpoints line `smartfactory plant --json` prints for it.
#pragma once

#include <filesystem>
#include <string>
#include <string_view>

#include "sf/factory/line_supervisor.hpp"

namespace sf::factory::line_rig {

inline constexpr const char* kLayout = SF_SOURCE_DIR "/layouts/prototype-line.yaml";

inline LineOptions options(const std::filesystem::path& run_dir) {
  LineOptions o;
  o.layout_file = kLayout;
  o.run_dir = run_dir;
  o.program = "/bin/sh";  // any program: the plan only names it
  o.opcua_base_port = 14850;
  o.modbus_base_port = 15020;
  o.ecat_base_port = 15980;
  o.partition = "line-test";
  return o;
}

// The plant's endpoints line with PLCs from `modbus` up on `host`; the smart robots' segments in
// UDP from `ecat` up, or, with `raw`, on the plant's interface of that name.
inline std::string endpoints_line(const line::Layout& layout, int modbus, int ecat,
                                  const std::string& host = "127.0.0.1", const std::string& raw = {}) {
  std::string list;
  auto add = [&](const std::string& machine, const char* protocol, const std::string& address) {
    list += (list.empty() ? "" : ",") + std::string(R"({"machine":")") + machine + R"(","protocol":")" +
            protocol + R"(","address":")" + address + R"("})";
  };
  auto at = [&host](int port) { return host + ":" + std::to_string(port); };
  for (const auto& b : layout.belts) {
    add(b.name, "modbus-tcp", at(modbus++));
  }
  add(layout.uploader.name, "modbus-tcp", at(modbus++));
  add(layout.downloader.name, "modbus-tcp", at(modbus++));
  for (const auto& r : layout.robots) {
    if (r.legacy()) {
      add(r.name, "modbus-tcp", at(modbus++));
    } else {
      raw.empty() ? add(r.name, "ethercat-udp", at(ecat++)) : add(r.name, "ethercat-raw", raw);
    }
  }
  add("plant", "control", at(40000));
  return R"({"endpoints":[)" + list + "]}";
}

inline const LineProcess* find(const LinePlan& plan, std::string_view name) {
  for (const auto& p : plan.processes) {
    if (p.name == name) {
      return &p;
    }
  }
  return nullptr;
}

}  // namespace sf::factory::line_rig
