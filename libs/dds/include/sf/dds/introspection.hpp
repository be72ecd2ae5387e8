// Introspection of the entity layout (DDS 1.4 §2.2.2: participant →
// publisher/subscriber → writers/readers, each bound to a topic), so tests can
// check that each shop-floor entity has exactly the readers and writers the
// paper gives it (§IV.B).
//
// inspect() walks this process's entities; discover() reads the built-in
// topics DCPSParticipant / DCPSPublication / DCPSSubscription (DDS 1.4
// §2.2.5) and so sees the layout of every participant in the domain,
// including other processes.
#pragma once

#include <chrono>
#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

#include "sf/core/clock.hpp"
#include "sf/core/result.hpp"
#include "sf/dds/participant.hpp"

namespace sf::dds {

struct EndpointInfo {
  std::string topic;
  std::string type;
  std::vector<std::string> partitions;
  friend bool operator==(const EndpointInfo&, const EndpointInfo&) = default;
};

struct EntityLayout {
  std::string participant;  // the participant's name (ENTITY_NAME / USER_DATA)
  std::string key;          // its GUID in hex
  DomainId domain = 0;
  std::vector<EndpointInfo> readers;
  std::vector<EndpointInfo> writers;

  [[nodiscard]] std::size_t readers_on(std::string_view topic) const;
  [[nodiscard]] std::size_t writers_on(std::string_view topic) const;
  // Sorted topic names, one per endpoint (duplicates kept).
  [[nodiscard]] std::vector<std::string> reader_topics() const;
  [[nodiscard]] std::vector<std::string> writer_topics() const;
};

// The readers and writers this process created under `participant`.
Result<EntityLayout> inspect(const Participant& participant);

// Every participant `observer` has discovered in its domain (itself included)
// after waiting `settle` on `clock`, with their endpoints. Participants whose
// endpoints are all outside `partition` are left out (empty: keep all).
Result<std::vector<EntityLayout>> discover(const Participant& observer, Clock& clock,
                                           std::chrono::nanoseconds settle, std::string_view partition = {});

// The layout as one JSON object (for CLI output and integration tests).
std::string to_json(const EntityLayout& layout);

}  // namespace sf::dds
