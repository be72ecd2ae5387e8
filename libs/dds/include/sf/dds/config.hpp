// Cyclone DDS configuration generated from a few settings, so a test host can
// run 50+ participants (processes) on loopback without touching system
// settings, and a plant host can bind one named interface.
//
// Loopback: the interface is "lo", multicast is off (lo has no MULTICAST
// flag), so SPDP discovery goes by unicast to 127.0.0.1 at the ports of every
// participant index 0..max_participant_index (Cyclone derives the unicast
// discovery port as 7400 + 250 * domain + 10 + 2 * index; DDSI-RTPS 2.2 §9.6.1.1).
// Keeping the index at most 119 keeps a domain's ports inside its own 250-port
// block, so domains 0..232 never collide.
//
// The XML goes to dds_create_domain() (Participant does that) or, for another
// program such as ddsperf, to the CYCLONEDDS_URI environment variable.
#pragma once

#include <chrono>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "sf/core/result.hpp"

namespace sf::dds {

using DomainId = std::uint32_t;
inline constexpr DomainId kMaxDomainId = 232;
inline constexpr int kMaxParticipantIndex = 119;

struct NetworkConfig {
  std::string interface = "lo";                 // a name ("eth0") or an address
  bool multicast = false;                       // SPDP/data multicast
  std::vector<std::string> peers{"127.0.0.1"};  // unicast discovery peers
  int max_participant_index = kMaxParticipantIndex;
  // Participant lease (DDSI SPDP lease): a peer that vanishes is removed after it.
  std::chrono::milliseconds lease_duration{5000};
  std::chrono::milliseconds spdp_interval{1000};
  // Internal/WriteBatch: a write leaves when its writer is flushed. Writer flushes after every
  // write, dispose and unregister; Writer::end_instances flushes once after many ends, which
  // then travel in one datagram.
  bool write_batch = true;
  // Internal/HeartbeatInterval: how often a reliable writer with unacknowledged data announces
  // it, for every writer of the participant including Cyclone's discovery writers. Unset:
  // Cyclone's default, 100 ms backing off towards 8 s. Set: this interval, without backing off
  // (it is also the attribute max, which bounds the backoff). A writer also asks for an
  // acknowledgement with the first write after 4/5 of an interval of quiet, which sends what its
  // batch holds. Longer means less traffic, and a lost sample is noticed later.
  std::optional<std::chrono::milliseconds> heartbeat_interval;
};

// Loopback only: lo, unicast discovery to 127.0.0.1, no multicast.
NetworkConfig loopback_network();
// One named interface with multicast discovery (the default plant setting).
NetworkConfig interface_network(std::string interface);

// Validates the settings and renders a <CycloneDDS> document for any domain id.
Result<std::string> cyclone_config_xml(const NetworkConfig& config);

Status validate_domain_id(DomainId domain);

}  // namespace sf::dds
