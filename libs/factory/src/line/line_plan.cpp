// The line's processes from its layout (line_supervisor.hpp): which processes, in which order,
// with which ports, and how the Supervisor recognises that each one is up.
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <memory>
#include <random>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "sf/core/process.hpp"
#include "sf/factory/line_supervisor.hpp"

namespace sf::factory {

namespace fs = std::filesystem;
using namespace std::chrono_literals;

namespace {

// True when 127.0.0.1:port can be bound now.
bool port_free(std::uint16_t port, bool udp) {
  const int fd = ::socket(AF_INET, (udp ? SOCK_DGRAM : SOCK_STREAM) | SOCK_CLOEXEC, 0);
  if (fd < 0) {
    return false;
  }
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_port = htons(port);
  a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  const bool ok = ::bind(fd, reinterpret_cast<const sockaddr*>(&a), sizeof a) == 0;
  ::close(fd);
  return ok;
}

std::string own_partition() {
  std::random_device random;
  return fmt::format("line-{}-{:08x}", ::getpid(), random());
}

// The machines with a controller of their own, in start order: smart robots, then gateways.
std::vector<LineProcess> controllers(const line::Layout& layout) {
  std::vector<LineProcess> out;
  for (const auto& r : layout.robots) {
    if (!r.legacy()) {
      out.push_back({r.name, LineRole::machine, GatewayKind::conveyor, {}, 0, {}});
    }
  }
  for (const auto& b : layout.belts) {
    out.push_back({b.name, LineRole::gateway, GatewayKind::conveyor, {}, 0, {}});
  }
  out.push_back({layout.uploader.name, LineRole::gateway, GatewayKind::uploader, {}, 0, {}});
  out.push_back({layout.downloader.name, LineRole::gateway, GatewayKind::downloader, {}, 0, {}});
  for (const auto& r : layout.robots) {
    if (r.legacy()) {
      out.push_back({r.name, LineRole::gateway, GatewayKind::legacy_robot, {}, 0, {}});
    }
  }
  return out;
}

// A base port for `count` ports: the given one (checked to fit) or a free range.
Status resolve_base(std::uint16_t& base, std::size_t count, bool udp, std::string_view what) {
  if (count == 0) {
    return {};
  }
  if (base == 0) {
    auto free = free_port_range(count, udp);
    if (!free) {
      return free.error().with_context(what);
    }
    base = *free;
    return {};
  }
  if (std::size_t{base} + count - 1 > 65535) {
    return make_error(Errc::invalid_argument,
                      fmt::format("{} {}: {} ports do not fit below 65536", what, base, count));
  }
  return {};
}

std::size_t plc_count(const line::Layout& layout) {
  std::size_t legacy = 0;
  for (const auto& r : layout.robots) {
    legacy += r.legacy() ? 1U : 0U;
  }
  return layout.belts.size() + 2 + legacy;
}

Status check_options(const LineOptions& o) {
  if (o.program.empty() || !fs::exists(o.program)) {
    return make_error(Errc::invalid_argument,
                      fmt::format("no smartfactory program at '{}'", o.program.string()));
  }
  if (!o.orders_file.empty() && !fs::is_regular_file(o.orders_file)) {
    return make_error(Errc::invalid_argument,
                      fmt::format("orders file '{}': no such file", o.orders_file.string()));
  }
  if (!o.historian.empty() && !o.cloud_config.empty()) {
    return make_error(Errc::invalid_argument, "a cloud config or a historian for a generated one, not both");
  }
  if (o.historian.empty() && !o.cloud_config.empty() && !fs::is_regular_file(o.cloud_config)) {
    return make_error(Errc::invalid_argument,
                      fmt::format("cloud config '{}': no such file", o.cloud_config.string()));
  }
  if (o.interface.empty()) {
    return make_error(Errc::invalid_argument, "the DDS interface is empty");
  }
  for (const char c : o.partition) {
    if (std::isalnum(static_cast<unsigned char>(c)) == 0 && c != '-' && c != '_' && c != '.') {
      return make_error(Errc::invalid_argument,
                        fmt::format("partition '{}': only letters, digits, '-', '_' and '.'", o.partition));
    }
  }
  return {};
}

// The plant's faces in the namespaces: Modbus and its control port on its field address, each
// smart robot's segment on its end of that robot's EtherCAT cable.
void add_plant_host_argv(const LinePlan& plan, LineProcess& p) {
  const auto* plant = plan.host_of(p);
  const auto field = plant->address(HostNetworkKind::field);
  p.argv.insert(p.argv.end(), {"--modbus-host", field, "--control-host", field});
  for (const auto& robot : plan.processes) {
    const auto* host = plan.host_of(robot);
    if (robot.role == LineRole::machine && host->on(HostNetworkKind::ethercat) != nullptr) {
      p.argv.insert(p.argv.end(),
                    {"--ecat-iface", robot.name + "=" + host->on(HostNetworkKind::ethercat)->peer});
    }
  }
}

std::vector<std::string> own_argv(const LinePlan& plan, const LineProcess& p) {
  const auto& o = plan.options;
  const std::string program = o.program.string();
  switch (p.role) {
    case LineRole::plant:
      return {program,
              "plant",
              "--json",
              "--status-interval",
              "0",
              "--modbus-port",
              std::to_string(o.modbus_base_port),
              "--ecat-port",
              std::to_string(o.ecat_base_port)};
    case LineRole::machine:
    case LineRole::gateway:
    case LineRole::orders:
      return {program, std::string(to_string(p.role)), "--config", p.config.string(), "--json"};
    case LineRole::cloud: {
      std::vector<std::string> argv{program,    "cloud",
                                    "--config", fs::absolute(o.cloud_config).string(),
                                    "--http",   std::to_string(o.http_port)};
      if (!o.web_users.empty()) {
        argv.insert(argv.end(), {"--web-users", fs::absolute(o.web_users).string()});
      }
      if (!o.tls_cert.empty()) {
        argv.insert(argv.end(), {"--tls-cert", fs::absolute(o.tls_cert).string(), "--tls-key",
                                 fs::absolute(o.tls_key).string()});
      }
      return argv;
    }
  }
  return {};
}

void add_argv(LinePlan& plan) {
  const auto& o = plan.options;
  const std::string layout = o.layout_file.empty() ? std::string() : fs::absolute(o.layout_file).string();
  for (auto& p : plan.processes) {
    p.argv = own_argv(plan, p);
    if (p.role == LineRole::plant) {
      if (!layout.empty()) {
        p.argv.insert(p.argv.end(), {"--layout", layout});
      }
      if (plan.hosts) {
        add_plant_host_argv(plan, p);
      }
    }
    if (const auto* host = plan.host_of(p)) {
      p.argv = in_namespace(*host, p.argv);
    }
  }
}

}  // namespace

std::string_view to_string(LineRole role) {
  constexpr std::string_view kNames[] = {"plant", "machine", "gateway", "cloud", "orders"};
  return kNames[static_cast<std::size_t>(role)];
}

Result<std::uint16_t> free_port_range(std::size_t count, bool udp) {
  std::random_device random;
  // Below Linux's default ephemeral range (32768..60999), where outgoing connections take theirs.
  std::uniform_int_distribution<int> pick(20000, 32000);
  for (int attempt = 0; attempt < 64; ++attempt) {
    const auto base = static_cast<std::uint16_t>(pick(random));
    bool all = true;
    for (std::size_t i = 0; i < count && all; ++i) {
      all = port_free(static_cast<std::uint16_t>(base + i), udp);
    }
    if (all) {
      return base;
    }
  }
  return make_error(Errc::io,
                    fmt::format("no {} free {} ports in a row on 127.0.0.1", count, udp ? "UDP" : "TCP"));
}

bool has_command(const fs::path& program, std::string_view command) {
  ProcessOptions o;
  o.argv = {program.string(), std::string(command), "--help"};
  o.in = Stdio::null();
  o.err = Stdio::null();
  auto done = Process::run(std::move(o), 10s);
  // An unknown command's --help is the program's own help (exit 0 too): the usage line tells.
  if (!done || !done->status.success()) {
    return false;
  }
  const auto usage = done->out.find("Usage: ");
  const auto end = done->out.find('\n', usage);
  return usage != std::string::npos &&
         done->out.substr(usage, end - usage).find(fmt::format(" {} ", command)) != std::string::npos;
}

Result<LinePlan> plan_line(LineOptions options) {
  SF_TRY(check_options(options));
  if (!options.historian.empty()) {  // the cloud's configuration is written for the line
    options.cloud_config = options.run_dir / "config" / "cloud.yaml";
  }
  auto layout = options.layout_file.empty() ? line::default_layout() : line::load_layout(options.layout_file);
  if (!layout) {
    return layout.error();
  }
  LinePlan plan{std::move(options), std::move(*layout), {}, std::nullopt};
  auto& o = plan.options;
  if (o.partition.empty()) {
    o.partition = own_partition();
  }
  if (o.run_dir.empty()) {
    o.run_dir = fs::temp_directory_path() / fmt::format("smartfactory-line-{}", ::getpid());
  }
  o.run_dir = fs::absolute(o.run_dir);
  auto machines = controllers(plan.layout);
  std::size_t smart = 0;
  for (const auto& m : machines) {
    smart += m.role == LineRole::machine ? 1U : 0U;
  }
  SF_TRY(resolve_base(o.opcua_base_port, machines.size() + (o.order_service ? 1U : 0U), false,
                      "--opcua-base-port"));
  SF_TRY(resolve_base(o.modbus_base_port, plc_count(plan.layout), false, "--modbus-base-port"));
  SF_TRY(resolve_base(o.ecat_base_port, smart, true, "EtherCAT UDP ports"));

  plan.processes.push_back({"plant", LineRole::plant, GatewayKind::conveyor, {}, 0, {}});
  std::uint16_t port = o.opcua_base_port;
  for (auto& m : machines) {
    m.config = o.run_dir / "config" / (m.name + ".yaml");
    m.opcua_port = port++;
    plan.processes.push_back(std::move(m));
  }
  if (!o.cloud_config.empty()) {
    plan.processes.push_back({"cloud", LineRole::cloud, GatewayKind::conveyor, {}, 0, {}});
  }
  if (o.order_service) {
    plan.processes.push_back(
        {"orders", LineRole::orders, GatewayKind::conveyor, o.run_dir / "config" / "orders.yaml", port, {}});
  }
  if (o.hosts) {
    auto hosts = plan_hosts(hosts_prefix(o.run_dir), plan.processes);
    if (!hosts) {
      return hosts.error();
    }
    plan.hosts = std::move(*hosts);
  }
  add_argv(plan);
  return plan;
}

const ProcessHost* LinePlan::host_of(const LineProcess& process) const {
  return hosts ? hosts->host(process.name) : nullptr;
}

std::optional<ReadyInfo> controller_ready(std::string_view line) {
  if (!line.starts_with('{')) {
    return std::nullopt;
  }
  const auto j = nlohmann::json::parse(line, nullptr, false);
  if (j.is_discarded() || !j.is_object() || j.value("event", "") != "ready") {
    return std::nullopt;
  }
  return ReadyInfo{j.value("opcua", "")};
}

SupervisorOptions line_supervisor_options(const LinePlan& plan) {
  SupervisorOptions o;
  o.log_dir = plan.options.run_dir / "log";
  return o;
}

std::vector<SupervisedProcess> supervised_processes(const LinePlan& plan) {
  auto shared = std::make_shared<const LinePlan>(plan);
  std::vector<SupervisedProcess> out;
  for (const auto& p : plan.processes) {
    SupervisedProcess s{p.name, p.argv, controller_ready, {}};
    if (p.role == LineRole::plant) {
      s.ready = [](std::string_view line) -> std::optional<ReadyInfo> {
        if (parse_plant_endpoints(line)) {
          return ReadyInfo{};
        }
        return std::nullopt;
      };
      s.on_ready = [shared](std::string_view line) -> Status {
        auto endpoints = parse_plant_endpoints(line);
        if (!endpoints) {
          return endpoints.error();
        }
        return write_controller_configs(*shared, *endpoints);
      };
    } else if (p.role == LineRole::cloud) {
      // `smartfactory cloud` prints one of these once its gateway runs.
      s.ready = [](std::string_view line) -> std::optional<ReadyInfo> {
        if (line.starts_with("aggregating server on port") || line.starts_with("gateway running")) {
          return ReadyInfo{};
        }
        return std::nullopt;
      };
    }
    out.push_back(std::move(s));
  }
  return out;
}

}  // namespace sf::factory
