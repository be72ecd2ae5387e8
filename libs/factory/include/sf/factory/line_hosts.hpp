// The line on several hosts (`smartfactory line --hosts`): every process in a network namespace of
// its own, standing in for its own computer, with a separate interface per protocol as the
// paper's IPCs have them (§VII.A, Table 1):
//
//   ethercat  a veth pair from the plant's namespace to each smart robot's (raw EtherCAT frames,
//             no IP): the robot's segment, its master on one end, the plant's ESCs on the other
//   field     Modbus TCP between the gateways and the plant's PLCs       10.77.1.0/24
//   dds       the Contract Net: order service, machines, gateways        10.77.2.0/24
//   opcua     every controller and the order service to the cloud       10.77.3.0/24
//
// Each shared network is a Linux bridge in the line's own namespace (<prefix>-net) with a veth
// port per member; a member's address is 10.77.<network>.<its start position + 1>, so the plant
// is 10.77.1.1. No namespace routes between its networks (forwarding stays off), so the cloud
// cannot reach the field or EtherCAT networks. IPv6 is off in every namespace: what crosses an
// interface is its protocol and the ARP that IPv4 needs.
//
// Namespaces are named <prefix>-<process>; the prefix comes from the run directory, so two lines
// at once (two run directories) never share a name, and a line started again in the same run
// directory finds what a crashed run left. The addresses are the same in every run: each run's
// networks live only in its own namespaces.
//
// HostPlan is data (names, addresses, who joins what, the `ip` commands it implies) and pure;
// HostNetworks runs the commands and removes everything again.
#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "sf/core/result.hpp"

namespace sf::factory {

enum class LineRole : std::uint8_t;
struct LineProcess;

enum class HostNetworkKind : std::uint8_t { ethercat, field, dds, opcua };
// "ethercat", "field", "dds", "opcua"
std::string_view to_string(HostNetworkKind kind);

// The first two octets of every network's addresses: 10.77.<network>.<host>.
inline constexpr std::string_view kHostsAddressPrefix = "10.77";

// One of the shared networks: a bridge in the line's namespace and a /24.
struct HostNetwork {
  HostNetworkKind kind = HostNetworkKind::field;
  std::string bridge;                      // "br-dds"
  int subnet = 0;                          // the third octet
  [[nodiscard]] std::string cidr() const;  // "10.77.2.0/24"
};

// One interface of a process's namespace: one end of a veth pair.
struct HostInterface {
  HostNetworkKind network = HostNetworkKind::field;
  std::string name;        // in the process's namespace: "ecat0", "field0", "dds0", "opcua0"
  std::string peer;        // the other end: a bridge port ("dds-3") or the plant's end ("ecat-1")
  std::string peer_netns;  // where the other end is: the line's namespace or the plant's
  std::string address;     // "10.77.2.3"; empty on EtherCAT (raw frames)
  bool makes_pair = true;  // the pair is made from this side (the plant's EtherCAT ends: the robot's)
};

struct ProcessHost {
  std::string process;  // the LineProcess's name
  std::string netns;    // "<prefix>-<process>"
  std::vector<HostInterface> interfaces;
  // Its interface on a network (for the plant on EtherCAT: the first), nullptr when it has none.
  [[nodiscard]] const HostInterface* on(HostNetworkKind network) const;
  // Its address on a network; empty when it has none.
  [[nodiscard]] std::string address(HostNetworkKind network) const;
};

struct HostPlan {
  std::string prefix;                 // "sf-3a9c1f"
  std::string line_netns;             // "<prefix>-net": the bridges
  std::vector<HostNetwork> networks;  // field, dds, opcua
  std::vector<ProcessHost> hosts;     // one per process, in start order
  [[nodiscard]] const ProcessHost* host(std::string_view process) const;
  // Every namespace of the plan: the line's, then the processes' in start order.
  [[nodiscard]] std::vector<std::string> namespaces() const;
};

// The networks a process of `role` joins (the plant also gets an EtherCAT end per smart robot).
std::vector<HostNetworkKind> networks_of(LineRole role);

// "sf-" and six hex digits of a hash of the (absolute) run directory.
std::string hosts_prefix(const std::filesystem::path& run_dir);

// The namespaces, interfaces and addresses of `processes` (the plant first, when there is one).
// Errc::invalid_argument: a prefix that is not [a-z0-9-] or too long, or more than 253 processes.
Result<HostPlan> plan_hosts(std::string prefix, const std::vector<LineProcess>& processes);

using Command = std::vector<std::string>;
// The commands that make the plan, in order: the namespaces, IPv6 off, loopback up, the bridges,
// then per process its veth pairs, addresses and links up.
std::vector<Command> host_setup_commands(const HostPlan& plan);
// `ip netns del` for every namespace, the processes' first (their veths go with them).
std::vector<Command> host_teardown_commands(const HostPlan& plan);
// `argv` run in the process's namespace: ip netns exec NS argv... (ip execs it: same pid).
std::vector<std::string> in_namespace(const ProcessHost& host, const std::vector<std::string>& argv);

// Whether this process can make the plan: root, and `ip` on the PATH. Errc::unsupported otherwise.
Status hosts_supported();

// The plan made real: created by create(), removed by remove() or the destructor.
class HostNetworks {
 public:
  // Removes namespaces with the plan's names first (a crashed run's, with whatever still runs in
  // them; their names go to `removed`), then runs the setup commands. On an error removes what it
  // made; the error names the command and quotes what `ip` said.
  static Result<std::unique_ptr<HostNetworks>> create(HostPlan plan,
                                                      std::vector<std::string>* removed = nullptr);
  ~HostNetworks();
  HostNetworks(const HostNetworks&) = delete;
  HostNetworks& operator=(const HostNetworks&) = delete;

  [[nodiscard]] const HostPlan& plan() const { return plan_; }
  // Deletes every namespace of the plan (idempotent); the first error, after trying them all.
  Status remove();

 private:
  explicit HostNetworks(HostPlan plan) : plan_(std::move(plan)) {}
  HostPlan plan_;
  bool made_ = false;
};

// Runs `fn` on this thread inside the namespace `netns`, then takes the thread back to its own.
// Sockets fn opens, and threads it starts (an OPC UA client's loop thread), stay in `netns`: how a
// program outside the line reaches a process on one of its networks.
Status with_netns(const std::string& netns, const std::function<void()>& fn);

// The namespaces of `names` that exist now (in /run/netns).
std::vector<std::string> existing_namespaces(const std::vector<std::string>& names);

}  // namespace sf::factory
