// The controllers' configurations of a line run (line_supervisor.hpp): YAML in the keys of
// controller_config.hpp, machine_config.hpp and gateway_config.hpp, pointing at the plant's
// actual addresses.
#include <fstream>
#include <system_error>

#include <fmt/format.h>
#include <yaml-cpp/yaml.h>
#include <nlohmann/json.hpp>

#include "sf/factory/line_supervisor.hpp"
#include "sf/line/ontology.hpp"

namespace sf::factory {

namespace fs = std::filesystem;

namespace {

const PlantEndpoint* find_endpoint(const std::vector<PlantEndpoint>& endpoints, std::string_view machine,
                                   std::string_view protocol) {
  for (const auto& e : endpoints) {
    if (e.machine == machine && e.protocol == protocol) {
      return &e;
    }
  }
  return nullptr;
}

// "host:port" split at its last colon.
Result<std::pair<std::string, std::uint16_t>> host_port(const PlantEndpoint& e) {
  const auto colon = e.address.rfind(':');
  if (colon != std::string::npos && colon > 0) {
    try {
      const int port = std::stoi(e.address.substr(colon + 1));
      if (port > 0 && port < 65536) {
        return std::pair{e.address.substr(0, colon), static_cast<std::uint16_t>(port)};
      }
    } catch (const std::exception&) {
    }
  }
  return make_error(Errc::malformed,
                    fmt::format("{} of {}: '{}' is not HOST:PORT", e.protocol, e.machine, e.address));
}

// An absolute path, so the configuration reads the same from any folder.
void path_key(YAML::Emitter& y, std::string_view key, const fs::path& path) {
  if (!path.empty()) {
    y << YAML::Key << std::string(key) << YAML::Value << fs::absolute(path).string();
  }
}

void opcua_and_dds_keys(YAML::Emitter& y, const LinePlan& plan, const LineProcess& p, bool open) {
  const ProcessHost* host = plan.host_of(p);
  y << YAML::Key << "opcua" << YAML::Value << YAML::Flow << YAML::BeginMap << YAML::Key << "port"
    << YAML::Value << p.opcua_port;
  if (host != nullptr) {  // only on its OPC UA network
    y << YAML::Key << "host" << YAML::Value << host->address(HostNetworkKind::opcua);
  }
  if (open) {
    // Orders from anyone on this host (or its OPC UA network), as configs/order-service.yaml.
    y << YAML::Key << "modes" << YAML::Value << "none";
  }
  // The line runs on one host (loopback, or namespaces of its own with --hosts): whoever may use
  // this host is its operator, and may Clear, Reset and Start a machine after a fault (OPC 30050
  // §6.7). A deployment across hosts gives each controller a users file instead (docs/opcua.md,
  // "Security").
  y << YAML::Key << "anonymous" << YAML::Value << "operator";
  y << YAML::EndMap;
  // With hosts: multicast discovery on its DDS network's interface only (sf::dds::interface_network).
  const std::string interface =
      host != nullptr ? host->on(HostNetworkKind::dds)->name : plan.options.interface;
  y << YAML::Key << "dds" << YAML::Value << YAML::Flow << YAML::BeginMap << YAML::Key << "interface"
    << YAML::Value << interface << YAML::Key << "partition" << YAML::Value << plan.options.partition
    << YAML::EndMap;
}

// The keys every controller has (controller_config.hpp).
void common_keys(YAML::Emitter& y, const LinePlan& plan, const LineProcess& p) {
  y << YAML::Key << "machine" << YAML::Value << p.name;
  path_key(y, "layout", plan.options.layout_file);
  y << YAML::Key << "start" << YAML::Value << "execute";
  opcua_and_dds_keys(y, plan, p, false);
}

// The order service's keys (order_service.hpp).
void order_service_keys(YAML::Emitter& y, const LinePlan& plan, const LineProcess& p) {
  path_key(y, "layout", plan.options.layout_file);
  path_key(y, "orders", plan.options.orders_file);
  opcua_and_dds_keys(y, plan, p, true);
}

// The smart robot's EtherCAT link: its own interface with hosts (the plant serves the segment on
// the other end of the cable), else the plant's EtherCAT-in-UDP address.
Result<std::string> ethercat_link(const LinePlan& plan, const LineProcess& p,
                                  const std::vector<PlantEndpoint>& endpoints) {
  const ProcessHost* host = plan.host_of(p);
  const char* protocol = host != nullptr ? "ethercat-raw" : "ethercat-udp";
  const PlantEndpoint* e = find_endpoint(endpoints, p.name, protocol);
  if (e == nullptr) {
    return make_error(Errc::not_found,
                      fmt::format("the plant serves no {} segment for {}", protocol, p.name));
  }
  if (host != nullptr) {
    return host->on(HostNetworkKind::ethercat)->name;
  }
  SF_TRY(host_port(*e));
  return "udp:" + e->address;
}

}  // namespace

Result<std::vector<PlantEndpoint>> parse_plant_endpoints(std::string_view line) {
  if (!line.starts_with('{')) {
    return make_error(Errc::malformed, "not the plant's endpoints line");
  }
  const auto j = nlohmann::json::parse(line, nullptr, false);
  if (j.is_discarded() || !j.is_object() || !j.contains("endpoints") || !j["endpoints"].is_array()) {
    return make_error(Errc::malformed, "not the plant's endpoints line");
  }
  std::vector<PlantEndpoint> out;
  for (const auto& e : j["endpoints"]) {
    if (!e.is_object() || !e.contains("machine") || !e["machine"].is_string() || !e.contains("protocol") ||
        !e["protocol"].is_string() || !e.contains("address") || !e["address"].is_string()) {
      return make_error(Errc::malformed,
                        fmt::format("plant endpoint {}: expected machine, protocol, address", e.dump()));
    }
    out.push_back(
        {e["machine"].get<std::string>(), e["protocol"].get<std::string>(), e["address"].get<std::string>()});
  }
  return out;
}

Result<std::string> controller_config_yaml(const LinePlan& plan, const LineProcess& p,
                                           const std::vector<PlantEndpoint>& endpoints) {
  YAML::Emitter y;
  y << YAML::BeginMap;
  if (p.role == LineRole::machine) {
    auto link = ethercat_link(plan, p, endpoints);
    if (!link) {
      return link.error();
    }
    common_keys(y, plan, p);
    y << YAML::Key << "ethercat" << YAML::Value << YAML::Flow << YAML::BeginMap << YAML::Key << "link"
      << YAML::Value << *link << YAML::EndMap;
  } else if (p.role == LineRole::gateway) {
    const PlantEndpoint* e = find_endpoint(endpoints, p.name, "modbus-tcp");
    if (e == nullptr) {
      return make_error(Errc::not_found, fmt::format("the plant serves no Modbus TCP PLC for {}", p.name));
    }
    auto address = host_port(*e);
    if (!address) {
      return address.error();
    }
    common_keys(y, plan, p);
    y << YAML::Key << "kind" << YAML::Value << std::string(to_string(p.kind));
    y << YAML::Key << "modbus" << YAML::Value << YAML::Flow << YAML::BeginMap << YAML::Key << "host"
      << YAML::Value << address->first << YAML::Key << "port" << YAML::Value << address->second
      << YAML::EndMap;
  } else if (p.role == LineRole::orders) {
    order_service_keys(y, plan, p);
  } else {
    return make_error(Errc::invalid_argument, fmt::format("{} has no generated configuration", p.name));
  }
  y << YAML::EndMap;
  if (!y.good()) {
    return make_error(Errc::state, fmt::format("configuration of {}: {}", p.name, y.GetLastError()));
  }
  return fmt::format("# {} on the line {}, written by `smartfactory line`\n{}\n", p.name, plan.layout.line,
                     y.c_str());
}

constexpr std::chrono::seconds kDueAfter{900};

std::string cloud_config_yaml(const LinePlan& plan) {
  YAML::Emitter y;
  y << YAML::BeginMap;
  y << YAML::Key << "historian" << YAML::Value << YAML::BeginMap << YAML::Key << "url" << YAML::Value
    << plan.options.historian << YAML::Key << "buffer" << YAML::Value
    << fs::absolute(plan.options.run_dir / "buffer").string() << YAML::EndMap;
  // With hosts, the aggregating server is for supervisory clients on the OPC UA network.
  const ProcessHost* cloud = plan.hosts ? plan.hosts->host("cloud") : nullptr;
  y << YAML::Key << "aggregating_server" << YAML::Value << YAML::Flow << YAML::BeginMap << YAML::Key << "host"
    << YAML::Value << (cloud != nullptr ? cloud->address(HostNetworkKind::opcua) : "127.0.0.1") << YAML::Key
    << "port" << YAML::Value << 0 << YAML::EndMap;
  y << YAML::Key << "servers" << YAML::Value << YAML::BeginSeq;
  for (const auto& p : plan.processes) {
    if (p.opcua_port == 0 || p.role == LineRole::cloud) {
      continue;
    }
    const bool orders = p.role == LineRole::orders;
    const ProcessHost* host = plan.host_of(p);
    y << YAML::BeginMap << YAML::Key << "name" << YAML::Value << p.name << YAML::Key << "url" << YAML::Value
      << fmt::format("opc.tcp://{}:{}", host != nullptr ? host->address(HostNetworkKind::opcua) : "127.0.0.1",
                     p.opcua_port);
    // The order service serves None on loopback or its OPC UA network (its generated configuration); the
    // controllers their default, secured endpoints with the installation's PKI.
    y << YAML::Key << "security" << YAML::Value << (orders ? "none" : "auto");
    if (orders) {  // every step of every order (OrderModel::raise)
      y << YAML::Key << "events" << YAML::Value << true;
    }
    y << YAML::Key << "subscribe" << YAML::Value << YAML::BeginSeq << YAML::Flow << YAML::BeginMap;
    y << YAML::Key << "browse_path" << YAML::Value
      << (orders ? std::string("/Objects/OrderService") : "/Objects/Machines/" + line::iri_name(p.name));
    y << YAML::Key << "depth" << YAML::Value << (orders ? 1 : 3) << YAML::EndMap << YAML::EndSeq
      << YAML::EndMap;
  }
  y << YAML::EndSeq;
  // The knowledge loop over the line's own layout (its individuals); an order is promised within
  // kDueAfter of its acceptance (the rule `late`).
  y << YAML::Key << "knowledge" << YAML::Value << YAML::BeginMap;
  if (!plan.options.layout_file.empty()) {
    y << YAML::Key << "layout" << YAML::Value << fs::absolute(plan.options.layout_file).string();
  }
  y << YAML::Key << "due_after_s" << YAML::Value << kDueAfter.count() << YAML::EndMap;
  y << YAML::EndMap;
  return fmt::format("# the cloud of the line {}, written by `smartfactory line`\n{}\n", plan.layout.line,
                     y.c_str());
}

Status write_cloud_config(const LinePlan& plan) {
  std::error_code ec;
  fs::create_directories(plan.options.cloud_config.parent_path(), ec);
  std::ofstream out(plan.options.cloud_config, std::ios::trunc);
  out << cloud_config_yaml(plan);
  if (!out.flush()) {
    return make_error(Errc::io, fmt::format("cannot write {}", plan.options.cloud_config.string()));
  }
  return {};
}

Status prepare_run_dir(const LinePlan& plan) {
  std::error_code ec;
  fs::create_directories(plan.options.run_dir, ec);
  if (ec) {
    return make_error(Errc::io,
                      fmt::format("run directory {}: {}", plan.options.run_dir.string(), ec.message()));
  }
  return plan.options.historian.empty() ? Status{} : write_cloud_config(plan);
}

Status write_controller_configs(const LinePlan& plan, const std::vector<PlantEndpoint>& endpoints) {
  for (const auto& p : plan.processes) {
    if (p.config.empty()) {
      continue;
    }
    auto yaml = controller_config_yaml(plan, p, endpoints);
    if (!yaml) {
      return yaml.error();
    }
    std::error_code ec;
    fs::create_directories(p.config.parent_path(), ec);
    // Written beside and renamed over, so a controller restarting now reads a whole file.
    const fs::path part = p.config.string() + ".part";
    {
      std::ofstream out(part, std::ios::trunc);
      out << *yaml;
      if (!out.flush()) {
        return make_error(Errc::io, fmt::format("cannot write {}", part.string()));
      }
    }
    fs::rename(part, p.config, ec);
    if (ec) {
      return make_error(Errc::io, fmt::format("cannot write {}: {}", p.config.string(), ec.message()));
    }
  }
  return {};
}

}  // namespace sf::factory
