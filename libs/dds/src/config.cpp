#include "sf/dds/config.hpp"

#include <algorithm>

#include <fmt/format.h>

namespace sf::dds {
namespace {

bool is_xml_safe(const std::string& s) {
  return !s.empty() && std::none_of(s.begin(), s.end(), [](char c) {
    return c == '<' || c == '>' || c == '&' || c == '"' || c == '\'' || static_cast<unsigned char>(c) < 0x20;
  });
}

std::string interface_xml(const std::string& interface) {
  // A dotted address selects by address, anything else by name.
  const bool address = std::all_of(interface.begin(), interface.end(),
                                   [](char c) { return (c >= '0' && c <= '9') || c == '.' || c == ':'; });
  return fmt::format("<Interfaces><NetworkInterface {}=\"{}\"/></Interfaces>", address ? "address" : "name",
                     interface);
}

}  // namespace

NetworkConfig loopback_network() {
  return NetworkConfig{};
}

NetworkConfig interface_network(std::string interface) {
  NetworkConfig c;
  c.interface = std::move(interface);
  c.multicast = true;
  c.peers.clear();
  c.lease_duration = std::chrono::milliseconds{10000};
  c.spdp_interval = std::chrono::milliseconds{5000};
  return c;
}

Status validate_domain_id(DomainId domain) {
  if (domain > kMaxDomainId) {
    return Error{
        Errc::invalid_argument,
        fmt::format("DDS domain id {} is above {} (its ports would exceed 65535)", domain, kMaxDomainId)};
  }
  return {};
}

Result<std::string> cyclone_config_xml(const NetworkConfig& c) {
  if (!is_xml_safe(c.interface)) {
    return Error{Errc::invalid_argument, fmt::format("bad network interface name '{}'", c.interface)};
  }
  if (c.max_participant_index < 0 || c.max_participant_index > kMaxParticipantIndex) {
    return Error{Errc::invalid_argument, fmt::format("max participant index {} outside 0..{}",
                                                     c.max_participant_index, kMaxParticipantIndex)};
  }
  if (c.lease_duration.count() <= 0 || c.spdp_interval.count() <= 0 ||
      (c.heartbeat_interval && c.heartbeat_interval->count() <= 0)) {
    return Error{Errc::invalid_argument, "lease duration, SPDP and heartbeat intervals must be positive"};
  }
  // max bounds Cyclone's backoff of the interval; equal to the interval, it does not back off.
  const std::string heartbeat =
      c.heartbeat_interval ? fmt::format("<HeartbeatInterval max=\"{0}ms\">{0}ms</HeartbeatInterval>",
                                         c.heartbeat_interval->count())
                           : std::string{};
  std::string peers;
  for (const auto& p : c.peers) {
    if (!is_xml_safe(p)) {
      return Error{Errc::invalid_argument, fmt::format("bad discovery peer '{}'", p)};
    }
    peers += fmt::format("<Peer address=\"{}\"/>", p);
  }
  return fmt::format(
      "<CycloneDDS><Domain Id=\"any\">"
      "<General>{}<AllowMulticast>{}</AllowMulticast></General>"
      "<Discovery><ParticipantIndex>auto</ParticipantIndex>"
      "<MaxAutoParticipantIndex>{}</MaxAutoParticipantIndex>"
      "{}<LeaseDuration>{}ms</LeaseDuration><SPDPInterval>{}ms</SPDPInterval></Discovery>"
      "<Internal><WriteBatch>{}</WriteBatch>{}</Internal>"
      "</Domain></CycloneDDS>",
      interface_xml(c.interface), c.multicast ? "true" : "false", c.max_participant_index,
      peers.empty() ? std::string{} : "<Peers>" + peers + "</Peers>", c.lease_duration.count(),
      c.spdp_interval.count(), c.write_batch ? "true" : "false", heartbeat);
}

}  // namespace sf::dds
