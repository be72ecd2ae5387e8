// What every shop-floor controller's configuration has (the smart robot's
// `machine` and a legacy machine's `gateway`): which machine of which layout
// it stands for, how it starts, its OPC UA port and its DDS settings for the
// Contract Net. The YAML keys are the same in both files:
//
//   machine: scara-robot-1            # the layout's name of the machine
//   layout: prototype-line.yaml       # relative to the file; built-in default when missing
//   serial_number: 0042               # Machinery identification (optional)
//   start: execute                    # stopped (default): wait for an operator's Reset and Start
//   job_timeout_s: 10                 # a job running this much longer than estimated fails
//   opcua:                            # the controller's own OPC UA server (its machine model)
//     port: 4841
//     host: 10.77.3.2                 # the address it listens on (default: every address)
//     modes: sign,encrypt             # none, sign, encrypt (comma list)
//     policies: Basic256Sha256        # comma list (default: the three the server offers)
//     users: users.yaml               # `opcua users` file; operators may call the PackML methods
//     anonymous: viewer               # a role or off (default: off with users, else viewer)
//     pki: pki                        # PKI folder (default: the installation's)
//     nodesets: [line.xml]            # NodeSet2 files first (`kb to-nodeset` of the ontology)
//   dds:                              # the Contract Net (paper §IV.B)
//     machining_domain: 10            # DDS domain ids, 0..232
//     conveying_domain: 11
//     interface: lo                   # lo: loopback only; a NIC name or address: multicast discovery
//     partition: smartfactory         # one per plant on a network
//     lease_ms: 1000                  # a controller silent this long is presumed dead by the products
#pragma once

#include <chrono>
#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "sf/core/config.hpp"
#include "sf/core/result.hpp"
#include "sf/line/layout.hpp"
#include "sf/negotiation/dds_transport.hpp"
#include "sf/opcua/server/security_setup.hpp"

namespace sf::factory {

struct DdsOptions {
  std::uint32_t machining_domain = 10;
  std::uint32_t conveying_domain = 11;
  std::string interface = "lo";
  std::string partition = "smartfactory";
  std::chrono::milliseconds lease{1000};
};

struct ControllerSettings {
  std::string machine;
  std::filesystem::path layout_file;  // empty: the built-in default layout
  std::string serial_number;
  bool auto_start = false;  // start: execute
  std::chrono::milliseconds job_timeout{10000};
  std::uint16_t opcua_port = 4840;
  std::string opcua_host;  // the address the server listens on and names in its URL; empty: all
  opcua::server::ServerSecuritySettings opcua_security;
  std::vector<std::string> opcua_nodesets;
  DdsOptions dds;
};

// The negotiation module's DDS settings for these options.
negotiation::DdsSettings dds_settings(const DdsOptions& options);

// Reads the common keys of `root` (a mapping already checked for unknown keys); relative file
// names are taken from `base` (the file's folder). `machine` is required unless settings.machine
// is set before (a process that is not a machine's controller names itself).
Status parse_controller_settings(const config::Node& root, ControllerSettings& settings,
                                 const std::filesystem::path& base = {});
// The layout the settings name, relative to `base`; errors point at the `layout` key.
Result<line::Layout> load_settings_layout(const config::Node& root, const ControllerSettings& settings,
                                          const std::filesystem::path& base);
// A duration key in units of `unit_ms` milliseconds (kDurationMs for "_ms" keys, kDurationSeconds
// for "_s"), 1 ms up to 11 days.
inline constexpr double kDurationMs = 1.0;
inline constexpr double kDurationSeconds = 1000.0;
Status read_duration(const config::Node& n, std::string_view key, double unit_ms,
                     std::chrono::milliseconds& out);

}  // namespace sf::factory
