// The smart robot's IPC configuration (`smartfactory machine --config FILE`,
// paper §VII.A): the common controller keys (controller_config.hpp) plus its
// EtherCAT segment and how it picks and places. Every key is checked; errors
// name file:line:column and the key path; a machine that is not a smart robot
// of the layout is refused.
//
//   machine: scara-robot-1
//   start: execute
//   ethercat:
//     link: udp:127.0.0.1:34980       # "udp:HOST:PORT" (EtherCAT in UDP, ETG.8200) or an interface (raw)
//     cycle_us: 1000                  # the CSP cycle
//     slave: 0                        # the smart controller's position in the segment
//     realtime: true                  # SCHED_FIFO for the cycle thread when allowed
//   pick_place:
//     approach_m: 0.05
//     release_m: 0.01
//     blend_m: 0.02
//     grip_timeout_ms: 300            # no part on the cup by then: the dispenser is empty
//     release_timeout_ms: 300
//   opcua: {port: 4850}
//   dds: {interface: lo}
#pragma once

#include <chrono>
#include <filesystem>
#include <string>
#include <string_view>

#include "sf/core/result.hpp"
#include "sf/factory/controller_config.hpp"
#include "sf/factory/smart_robot.hpp"
#include "sf/line/layout.hpp"

namespace sf::factory {

struct EtherCatOptions {
  std::string link = "udp:127.0.0.1:34980";
  std::chrono::microseconds cycle{1000};
  std::size_t slave = 0;
  bool realtime = true;
};

struct MachineConfig {
  ControllerSettings controller;
  EtherCatOptions ethercat;
  PickPlace pick_place;
};

struct MachineSetup {
  MachineConfig config;
  line::Layout layout;
};

Result<MachineSetup> load_machine_config(const std::filesystem::path& file);
// `name` stands for the file in errors; a relative layout path is taken from `base`.
Result<MachineSetup> parse_machine_config(std::string_view yaml, std::string name = "<machine>",
                                          const std::filesystem::path& base = {});

// The controller's configuration from the machine's.
SmartRobotConfig smart_robot_config(const MachineConfig& config);

}  // namespace sf::factory
