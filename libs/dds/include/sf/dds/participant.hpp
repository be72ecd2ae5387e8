// Participant: one DomainParticipant (DDS 1.4 §2.2.2.2.1) with the publisher
// and subscriber its writers and readers hang off. The paper gives each
// machine and conveyor one participant and each product two (§IV.B).
//
// The domain is created explicitly with the given Cyclone XML (shared by all
// participants of this process in that domain); an empty config falls back
// to Cyclone's own (CYCLONEDDS_URI). The partition isolates test runs and
// plants sharing a network: endpoints in different partitions never match.
#pragma once

#include <memory>
#include <string>

#include <dds/dds.h>

#include "sf/core/result.hpp"
#include "sf/dds/config.hpp"
#include "sf/dds/entity.hpp"

namespace sf::dds {

struct ParticipantOptions {
  std::string config;     // Cyclone XML (cyclone_config_xml), empty = Cyclone's default
  std::string name;       // ENTITY_NAME and USER_DATA of the participant (seen by peers)
  std::string partition;  // PARTITION of its publisher and subscriber; empty = default partition
};

namespace detail {
struct DomainHandle;
}

class Participant {
 public:
  static Result<Participant> create(DomainId domain, ParticipantOptions options = {});

  Participant(Participant&&) noexcept = default;
  Participant& operator=(Participant&&) noexcept = default;
  ~Participant();

  [[nodiscard]] dds_entity_t handle() const { return participant_.get(); }
  [[nodiscard]] dds_entity_t publisher() const { return publisher_; }
  [[nodiscard]] dds_entity_t subscriber() const { return subscriber_; }
  [[nodiscard]] DomainId domain_id() const { return domain_id_; }
  [[nodiscard]] const std::string& name() const { return name_; }
  [[nodiscard]] const std::string& partition() const { return partition_; }

 private:
  Participant() = default;

  // Declared first so it is destroyed last: the domain outlives its participants.
  std::shared_ptr<detail::DomainHandle> domain_;
  Entity participant_;
  dds_entity_t publisher_ = 0;  // children of participant_, deleted with it
  dds_entity_t subscriber_ = 0;
  DomainId domain_id_ = 0;
  std::string name_;
  std::string partition_;
};

}  // namespace sf::dds
