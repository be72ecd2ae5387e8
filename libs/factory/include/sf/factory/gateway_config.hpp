// A legacy machine's gateway configuration (the paper's Raspberry Pi next to
// a closed PLC, §VII.B): which machine of the layout it stands for, how it
// reaches the PLC, and what it offers on the machine's behalf. Every key is
// checked; errors name file:line:column and the key path, and a
// configuration that does not fit its layout (no such machine, a machine of
// another kind, a station the robot does not serve) is refused. The keys
// every controller has (machine, layout, serial_number, start, job_timeout_s,
// opcua, dds) are controller_config.hpp's; a gateway adds:
//
//   kind: legacy-robot                # conveyor, uploader, downloader, legacy-robot
//   modbus:
//     host: 127.0.0.1
//     port: 1502                      # default: the layout's controller/plc port
//     unit_id: 255
//     timeout_ms: 500                 # response timeout
//     poll_period_ms: 20
//     stale_after_ms: 1000            # values read this long ago turn from Uncertain to Bad
//   robot:                            # legacy-robot only: the controller's taught program
//     station: conveyor3/toshiba      # where it loads boxes (default: its first station)
//     approach_m: 0.05                # above pick and place points
//     release_above_m: 0.01           # above the box top when releasing
//     home_above_m: 0.15              # home: above its first station
//     grip_s: 0.15                    # the gripper closing or opening
#pragma once

#include <chrono>
#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>

#include "sf/core/result.hpp"
#include "sf/factory/controller_config.hpp"
#include "sf/line/layout.hpp"

namespace sf::factory {

enum class GatewayKind : std::uint8_t { conveyor, uploader, downloader, legacy_robot };
// "conveyor", "uploader", "downloader", "legacy-robot"
std::string_view to_string(GatewayKind kind);

struct ModbusEndpoint {
  std::string host = "127.0.0.1";
  std::uint16_t port = 0;  // 0: the layout's port for the machine
  std::uint8_t unit_id = 0xFF;
  std::chrono::milliseconds timeout{500};
  std::chrono::milliseconds poll_period{20};
  std::chrono::milliseconds stale_after{1000};
};

// A legacy robot controller's own program: its moves as taught on the
// controller, which the gateway cannot read over Modbus but needs for its
// estimates. The defaults are the line's controllers (docs/plant.md).
struct RobotProgram {
  std::string station;  // "belt/station" it loads boxes at; empty: its first
  double approach_m = 0.05;
  double release_above_m = 0.01;
  double home_above_m = 0.15;
  std::chrono::milliseconds grip{150};
};

struct GatewayConfig {
  ControllerSettings controller;  // machine, layout, start, job timeout, OPC UA, DDS
  GatewayKind kind = GatewayKind::conveyor;
  ModbusEndpoint modbus;
  RobotProgram robot;
};

// A configuration with the layout it was checked against.
struct GatewaySetup {
  GatewayConfig config;
  line::Layout layout;
};

// Reads `file` and the layout it names, and checks one against the other.
Result<GatewaySetup> load_gateway_config(const std::filesystem::path& file);
// The same for YAML text; `name` stands for the file in errors, `base` is the
// folder a relative layout path starts from.
Result<GatewaySetup> parse_gateway_config(std::string_view yaml, std::string name = "<gateway>",
                                          const std::filesystem::path& base = {});

}  // namespace sf::factory
