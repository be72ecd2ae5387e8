#include "sf/dds/participant.hpp"

#include <map>
#include <mutex>

#include <fmt/format.h>

#include "sf/dds/qos.hpp"

namespace sf::dds {
namespace detail {

// A Cyclone domain created with dds_create_domain(): one per domain id and
// process, shared by that domain's participants, deleted with the last one.
struct DomainHandle {
  DomainHandle(Entity d, std::string c) : domain(std::move(d)), config(std::move(c)) {}
  DomainHandle(const DomainHandle&) = delete;
  DomainHandle& operator=(const DomainHandle&) = delete;
  ~DomainHandle();

  Entity domain;
  std::string config;
};

}  // namespace detail
namespace {

std::mutex& registry_mutex() {
  static std::mutex m;
  return m;
}

std::map<DomainId, std::weak_ptr<detail::DomainHandle>>& registry() {
  static std::map<DomainId, std::weak_ptr<detail::DomainHandle>> domains;
  return domains;
}

Result<std::shared_ptr<detail::DomainHandle>> acquire_domain(DomainId id, const std::string& config) {
  const std::lock_guard lock{registry_mutex()};
  auto& slot = registry()[id];
  if (auto existing = slot.lock()) {
    if (existing->config != config) {
      return Error{Errc::invalid_argument,
                   fmt::format("DDS domain {} already runs with another configuration in this process", id)};
    }
    return existing;
  }
  const dds_entity_t handle = dds_create_domain(id, config.c_str());
  if (handle < 0) {
    return dds_error(handle, fmt::format("dds_create_domain({})", id));
  }
  auto domain = std::make_shared<detail::DomainHandle>(Entity{handle}, config);
  slot = domain;
  return domain;
}

Result<dds_entity_t> create_group(dds_entity_t participant, bool publisher, const std::string& partition) {
  QosBuilder b;
  if (!partition.empty()) {
    b.partition(partition);
  }
  const Qos qos = b.build();
  const dds_entity_t e = publisher ? dds_create_publisher(participant, qos.get(), nullptr)
                                   : dds_create_subscriber(participant, qos.get(), nullptr);
  if (e < 0) {
    return dds_error(e, publisher ? "dds_create_publisher" : "dds_create_subscriber");
  }
  return e;
}

}  // namespace

detail::DomainHandle::~DomainHandle() {
  // Under the registry lock, so a participant created concurrently for the
  // same id never sees a half-deleted domain.
  const std::lock_guard lock{registry_mutex()};
  domain.reset();
}

Result<Participant> Participant::create(DomainId domain, ParticipantOptions options) {
  SF_TRY(validate_domain_id(domain));
  Participant p;
  if (!options.config.empty()) {
    auto d = acquire_domain(domain, options.config);
    if (!d) {
      return d.error();
    }
    p.domain_ = std::move(*d);
  }
  QosBuilder qb;
  if (!options.name.empty()) {
    qb.entity_name(options.name).user_data(options.name);
  }
  const dds_entity_t handle = dds_create_participant(domain, qb.build().get(), nullptr);
  if (handle < 0) {
    return dds_error(handle, fmt::format("dds_create_participant(domain {})", domain));
  }
  p.participant_ = Entity{handle};
  auto pub = create_group(handle, true, options.partition);
  if (!pub) {
    return pub.error();
  }
  auto sub = create_group(handle, false, options.partition);
  if (!sub) {
    return sub.error();
  }
  p.publisher_ = *pub;
  p.subscriber_ = *sub;
  p.domain_id_ = domain;
  p.name_ = std::move(options.name);
  p.partition_ = std::move(options.partition);
  return p;
}

Participant::~Participant() {
  // Explicit order: the participant (and all its children) before the domain.
  participant_.reset();
  domain_.reset();
}

}  // namespace sf::dds
