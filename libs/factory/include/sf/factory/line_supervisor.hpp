// The line as processes (`smartfactory line`, the deployment of paper §VII on one host): from a
// layout, the processes of the line and the configuration each one needs, generated into a run
// directory, in the order they start:
//   plant         `smartfactory plant`: the hardware (EtherCAT segments, Modbus PLCs)
//   <smart robot> `smartfactory machine` per smart robot (its IPC, §VII.A)
//   <machine>     `smartfactory gateway` per belt, uploader, downloader and legacy robot (§VII.B)
//   cloud         `smartfactory cloud` with a given cloud.yaml (optional)
//   orders        `smartfactory orders`: the order service, home of the product agents
// The controllers' configurations point at the plant's actual addresses, so they are written
// when the plant prints its endpoints line. Everything is on loopback; OPC UA ports count up from
// a base port; every process of a run shares one DDS partition, so parallel runs do not meet.
// With `hosts`, every process runs in a network namespace of its own with an interface per
// protocol (line_hosts.hpp), and the configurations name those interfaces and addresses.
//
// Run directory: config/<name>.yaml (the controllers' and the order service's configurations),
// log/<name>.log (each process's stdout and stderr, appended across restarts).
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "sf/core/result.hpp"
#include "sf/factory/gateway_config.hpp"
#include "sf/factory/line_hosts.hpp"
#include "sf/factory/supervisor.hpp"
#include "sf/line/layout.hpp"

namespace sf::factory {

struct LineOptions {
  std::filesystem::path layout_file;  // empty: the built-in default layout
  std::filesystem::path run_dir;
  std::filesystem::path program;  // the smartfactory binary the processes run
  // OPC UA ports: the controllers' base, base + 1, ... in start order, then the order service.
  // 0: a free range.
  std::uint16_t opcua_base_port = 4850;
  // The plant's Modbus servers (base + the PLC's index) and EtherCAT segments; 0: a free range.
  // Fixed for the run, so a restarted plant is found where its controllers look.
  std::uint16_t modbus_base_port = 0;
  std::uint16_t ecat_base_port = 0;
  std::string partition;  // DDS partition; empty: one of its own for this run
  std::string interface = "lo";
  bool order_service = true;
  std::filesystem::path orders_file;   // orders the order service takes at its start (optional)
  std::filesystem::path cloud_config;  // empty: no cloud (unless `historian` is set)
  // A historian URL (sqlite:PATH, postgresql://...): the cloud runs with a configuration written
  // for the line (write_cloud_config: every controller's and the order service's OPC UA server).
  std::string historian;
  // Each process in a network namespace of its own (line_hosts.hpp), named from the run directory.
  bool hosts = false;
  // The cloud's dashboard (`smartfactory cloud --http`): its port (0: any free one, printed in
  // the cloud's log; -1: off) and its users file.
  int http_port = -1;
  std::filesystem::path web_users;
  // Both set: the dashboard over HTTPS and WSS (`smartfactory cloud --tls-cert --tls-key`).
  std::filesystem::path tls_cert;
  std::filesystem::path tls_key;
};

enum class LineRole : std::uint8_t { plant, machine, gateway, cloud, orders };
// "plant", "machine", "gateway", "cloud", "orders"
std::string_view to_string(LineRole role);

struct LineProcess {
  std::string name;  // the machine's name; "plant", "cloud", "orders"
  LineRole role = LineRole::plant;
  GatewayKind kind = GatewayKind::conveyor;  // gateways
  std::filesystem::path config;              // machine, gateway, orders: written when the plant is up
  std::uint16_t opcua_port = 0;              // 0: none (plant), or as its own config says (cloud)
  std::vector<std::string> argv;
};

struct LinePlan {
  LineOptions options;  // with ports and partition resolved
  line::Layout layout;
  std::vector<LineProcess> processes;  // in start order, argv in their namespaces with `hosts`
  std::optional<HostPlan> hosts;       // with options.hosts
  // The process's place in the host plan; nullptr without one.
  [[nodiscard]] const ProcessHost* host_of(const LineProcess& process) const;
};

// One of the plant's faces, from its `--json` endpoints line.
struct PlantEndpoint {
  std::string machine;
  std::string protocol;  // "modbus-tcp", "ethercat-udp", "ethercat-raw", "control"
  std::string address;   // "127.0.0.1:1502"
};

// Checks the layout and the options and lists the processes; writes nothing, starts nothing.
// Errc::invalid_argument (or the layout's error) when the line cannot be planned.
Result<LinePlan> plan_line(LineOptions options);

// The plant's endpoints from its `{"endpoints": [...]}` line.
Result<std::vector<PlantEndpoint>> parse_plant_endpoints(std::string_view line);

// The configuration (YAML) of a `machine`, `gateway` or `orders` process for the plant's endpoints.
Result<std::string> controller_config_yaml(const LinePlan& plan, const LineProcess& process,
                                           const std::vector<PlantEndpoint>& endpoints);
// Writes every configuration of the run into the run directory.
Status write_controller_configs(const LinePlan& plan, const std::vector<PlantEndpoint>& endpoints);

// The cloud's configuration for a plan with `historian` set (YAML): the historian, its store-and-
// forward buffer in the run directory, and every OPC UA server of the line with what the cloud
// keeps of it (a machine's PackML state, job and identification; the order service's counters,
// events and inspections).
std::string cloud_config_yaml(const LinePlan& plan);
// Writes it to plan.options.cloud_config.
Status write_cloud_config(const LinePlan& plan);
// Creates the run directory and, for a plan with `historian` set, writes the cloud's configuration.
Status prepare_run_dir(const LinePlan& plan);

// The processes for a Supervisor: argv, ready lines, and the plant's ready line writing the
// controllers' configurations.
std::vector<SupervisedProcess> supervised_processes(const LinePlan& plan);

// The supervisor options for a plan (log folder in the run directory).
SupervisorOptions line_supervisor_options(const LinePlan& plan);

// A ready line of `machine`, `gateway`, `orders` ({"event":"ready",...,"opcua":URL}).
std::optional<ReadyInfo> controller_ready(std::string_view line);

// Whether `program` has the command (`program COMMAND --help` succeeds).
bool has_command(const std::filesystem::path& program, std::string_view command);

// `count` consecutive ports on 127.0.0.1 that are free now, for TCP (stream) or UDP.
Result<std::uint16_t> free_port_range(std::size_t count, bool udp);

}  // namespace sf::factory
