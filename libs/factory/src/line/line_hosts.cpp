// The line's namespaces, interfaces and addresses (line_hosts.hpp): data and the `ip` commands it
// implies, nothing run here.
#include <algorithm>
#include <cctype>
#include <cstdint>

#include <fmt/format.h>

#include "sf/factory/line_hosts.hpp"
#include "sf/factory/line_supervisor.hpp"

namespace sf::factory {

namespace {

constexpr std::size_t kMaxHosts = 253;  // .1 .. .253 of a /24 (.0 names the network, .255 broadcasts)
constexpr std::size_t kMaxPrefix = 32;

// The shared networks, in the order of HostNetworkKind, and their third octets.
constexpr HostNetworkKind kShared[] = {HostNetworkKind::field, HostNetworkKind::dds, HostNetworkKind::opcua};

int subnet_of(HostNetworkKind kind) {
  return static_cast<int>(kind);  // field 1, dds 2, opcua 3
}

// The interface's name inside a process's namespace: one per protocol, so "ecat0", "dds0", ...
std::string own_name(HostNetworkKind kind) {
  return kind == HostNetworkKind::ethercat ? "ecat0" : fmt::format("{}0", to_string(kind));
}

bool name_ok(std::string_view name, bool lower_only) {
  return !name.empty() && std::all_of(name.begin(), name.end(), [lower_only](char c) {
    const auto u = static_cast<unsigned char>(c);
    return std::islower(u) != 0 || std::isdigit(u) != 0 || c == '-' ||
           (!lower_only && (std::isupper(u) != 0 || c == '_' || c == '.'));
  });
}

Status check(const std::string& prefix, const std::vector<LineProcess>& processes) {
  if (!name_ok(prefix, true) || prefix.size() > kMaxPrefix) {
    return make_error(Errc::invalid_argument,
                      fmt::format("namespace prefix '{}': up to {} of a-z, 0-9 and '-'", prefix, kMaxPrefix));
  }
  if (processes.size() > kMaxHosts) {
    return make_error(
        Errc::invalid_argument,
        fmt::format("{} processes do not fit the /24 of a network ({} do)", processes.size(), kMaxHosts));
  }
  for (const auto& p : processes) {
    if (!name_ok(p.name, false) || p.name == "net") {
      return make_error(Errc::invalid_argument,
                        fmt::format("process '{}' cannot name a network namespace", p.name));
    }
  }
  return {};
}

Command ip_in(const std::string& netns, std::initializer_list<std::string> args) {
  Command c{"ip", "-n", netns};
  c.insert(c.end(), args.begin(), args.end());
  return c;
}

// The veth pair of one interface (made from the process's side), its addresses and links up.
void interface_commands(const ProcessHost& h, const HostInterface& i, std::vector<Command>& out) {
  out.push_back(
      ip_in(h.netns, {"link", "add", i.name, "type", "veth", "peer", "name", i.peer, "netns", i.peer_netns}));
  if (i.network == HostNetworkKind::ethercat) {
    out.push_back(ip_in(i.peer_netns, {"link", "set", i.peer, "up"}));
  } else {
    out.push_back(ip_in(i.peer_netns,
                        {"link", "set", i.peer, "master", fmt::format("br-{}", to_string(i.network)), "up"}));
    out.push_back(ip_in(h.netns, {"addr", "add", i.address + "/24", "dev", i.name}));
  }
  out.push_back(ip_in(h.netns, {"link", "set", i.name, "up"}));
}

}  // namespace

std::string_view to_string(HostNetworkKind kind) {
  constexpr std::string_view kNames[] = {"ethercat", "field", "dds", "opcua"};
  return kNames[static_cast<std::size_t>(kind)];
}

std::string HostNetwork::cidr() const {
  return fmt::format("{}.{}.0/24", kHostsAddressPrefix, subnet);
}

const HostInterface* ProcessHost::on(HostNetworkKind network) const {
  for (const auto& i : interfaces) {
    if (i.network == network) {
      return &i;
    }
  }
  return nullptr;
}

std::string ProcessHost::address(HostNetworkKind network) const {
  const auto* i = on(network);
  return i == nullptr ? std::string() : i->address;
}

const ProcessHost* HostPlan::host(std::string_view process) const {
  for (const auto& h : hosts) {
    if (h.process == process) {
      return &h;
    }
  }
  return nullptr;
}

std::vector<std::string> HostPlan::namespaces() const {
  std::vector<std::string> out{line_netns};
  for (const auto& h : hosts) {
    out.push_back(h.netns);
  }
  return out;
}

std::vector<HostNetworkKind> networks_of(LineRole role) {
  using K = HostNetworkKind;
  switch (role) {
    case LineRole::plant:
      return {K::field};
    case LineRole::machine:
      return {K::ethercat, K::dds, K::opcua};
    case LineRole::gateway:
      return {K::field, K::dds, K::opcua};
    case LineRole::orders:
      return {K::dds, K::opcua};
    case LineRole::cloud:
      return {K::opcua};
  }
  return {};
}

std::string hosts_prefix(const std::filesystem::path& run_dir) {
  // FNV-1a (32 bit) of the path, folded to 24 bits: short names, different for different runs.
  auto path = std::filesystem::absolute(run_dir).lexically_normal();
  if (!path.has_filename()) {  // "run/" names "run"
    path = path.parent_path();
  }
  std::uint32_t hash = 2166136261U;
  for (const char c : path.string()) {
    hash = (hash ^ static_cast<unsigned char>(c)) * 16777619U;
  }
  return fmt::format("sf-{:06x}", ((hash >> 24U) ^ hash) & 0xffffffU);
}

Result<HostPlan> plan_hosts(std::string prefix, const std::vector<LineProcess>& processes) {
  SF_TRY(check(prefix, processes));
  HostPlan plan;
  plan.line_netns = prefix + "-net";
  plan.prefix = std::move(prefix);
  for (const auto kind : kShared) {
    plan.networks.push_back({kind, fmt::format("br-{}", to_string(kind)), subnet_of(kind)});
  }
  std::size_t plant = processes.size();
  for (std::size_t i = 0; i < processes.size(); ++i) {
    plant = processes[i].role == LineRole::plant && plant == processes.size() ? i : plant;
  }
  for (std::size_t i = 0; i < processes.size(); ++i) {
    const auto& p = processes[i];
    ProcessHost h{p.name, fmt::format("{}-{}", plan.prefix, p.name), {}};
    for (const auto kind : networks_of(p.role)) {
      HostInterface in{
          kind, own_name(kind), fmt::format("{}-{}", to_string(kind), i + 1), plan.line_netns, {}, true};
      if (kind == HostNetworkKind::ethercat) {
        if (plant >= i) {
          return make_error(Errc::invalid_argument,
                            fmt::format("{} is a smart robot, but no plant starts before it", p.name));
        }
        in.peer = fmt::format("ecat-{}", i + 1);
        in.peer_netns = fmt::format("{}-{}", plan.prefix, processes[plant].name);
        // The plant's end of the cable, in the plant's list (made from the robot's side).
        plan.hosts[plant].interfaces.push_back({kind, in.peer, in.name, h.netns, {}, false});
      } else {
        in.address = fmt::format("{}.{}.{}", kHostsAddressPrefix, subnet_of(kind), i + 1);
      }
      h.interfaces.push_back(std::move(in));
    }
    plan.hosts.push_back(std::move(h));
  }
  return plan;
}

std::vector<Command> host_setup_commands(const HostPlan& plan) {
  std::vector<Command> out;
  for (const auto& ns : plan.namespaces()) {
    out.push_back({"ip", "netns", "add", ns});
    // IPv4 only, and no namespace forwards between its networks.
    out.push_back({"ip", "netns", "exec", ns, "sysctl", "-q", "-w", "net.ipv6.conf.all.disable_ipv6=1",
                   "net.ipv6.conf.default.disable_ipv6=1", "net.ipv4.ip_forward=0"});
    out.push_back(ip_in(ns, {"link", "set", "lo", "up"}));
  }
  for (const auto& n : plan.networks) {
    // Without snooping the bridge floods multicast to every port: DDS discovery (SPDP) reaches
    // every participant without an IGMP querier on the network.
    out.push_back(ip_in(plan.line_netns, {"link", "add", n.bridge, "type", "bridge", "mcast_snooping", "0"}));
    out.push_back(ip_in(plan.line_netns, {"link", "set", n.bridge, "up"}));
  }
  for (const auto& h : plan.hosts) {
    for (const auto& i : h.interfaces) {
      if (i.makes_pair) {
        interface_commands(h, i, out);
      }
    }
  }
  return out;
}

std::vector<Command> host_teardown_commands(const HostPlan& plan) {
  std::vector<Command> out;
  for (auto it = plan.hosts.rbegin(); it != plan.hosts.rend(); ++it) {
    out.push_back({"ip", "netns", "del", it->netns});
  }
  out.push_back({"ip", "netns", "del", plan.line_netns});
  return out;
}

std::vector<std::string> in_namespace(const ProcessHost& host, const std::vector<std::string>& argv) {
  std::vector<std::string> out{"ip", "netns", "exec", host.netns};
  out.insert(out.end(), argv.begin(), argv.end());
  return out;
}

}  // namespace sf::factory
