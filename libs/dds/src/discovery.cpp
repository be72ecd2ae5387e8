// discover(): the domain's entity layout from the built-in topics.
#include <map>

#include <fmt/format.h>

#include "sf/dds/introspection.hpp"
#include "sf/dds/qos.hpp"
#include "sf/dds/reader.hpp"

namespace sf::dds {
namespace {

std::string hex_key(const dds_guid_t& guid) {
  std::string out;
  for (const auto b : guid.v) {
    out += fmt::format("{:02x}", b);
  }
  return out;
}

// The key of the participant a GUID belongs to: DDSI-RTPS 2.2 §8.2.4.3, an
// entity's GUID shares the participant's 12-byte prefix.
std::string participant_prefix(const std::string& hex) {
  return hex.substr(0, 24);
}

Result<Entity> builtin_reader(const Participant& p, dds_entity_t topic) {
  const dds_entity_t r = dds_create_reader(p.handle(), topic, nullptr, nullptr);
  if (r < 0) {
    return dds_error(r, "built-in topic reader");
  }
  return Entity{r};
}

std::string name_of(const dds_qos_t* qos) {
  if (qos == nullptr) {
    return {};
  }
  char* name = nullptr;
  if (dds_qget_entity_name(qos, &name) && name != nullptr) {
    std::string s{name};
    dds_free(name);
    return s;
  }
  void* data = nullptr;
  std::size_t size = 0;
  if (dds_qget_userdata(qos, &data, &size) && data != nullptr) {
    std::string s(static_cast<const char*>(data), size);
    dds_free(data);
    return s;
  }
  return {};
}

std::vector<std::string> partitions_of(const dds_qos_t* qos) {
  std::vector<std::string> out;
  std::uint32_t n = 0;
  char** names = nullptr;
  if (qos != nullptr && dds_qget_partition(qos, &n, &names)) {
    for (std::uint32_t i = 0; i < n; ++i) {
      out.emplace_back(names[i]);
      dds_free(names[i]);
    }
    dds_free(static_cast<void*>(names));
  }
  return out;
}

Status read_all(dds_entity_t reader, const RawSampleFn& fn) {
  for (;;) {
    auto n = ReaderBase::take_raw(reader, 256, fn);
    if (!n) {
      return n.error();
    }
    if (*n < 256) {
      return {};
    }
  }
}

Status read_endpoints(dds_entity_t reader, std::map<std::string, EntityLayout>& by_key, bool writers) {
  return read_all(reader, [&](const void* s, const SampleInfo& info) {
    if (!info.valid_data || info.instance_state != InstanceState::Alive) {
      return;
    }
    const auto* e = static_cast<const dds_builtintopic_endpoint_t*>(s);
    auto& layout = by_key[participant_prefix(hex_key(e->participant_key))];
    EndpointInfo ep{e->topic_name != nullptr ? e->topic_name : "",
                    e->type_name != nullptr ? e->type_name : "", partitions_of(e->qos)};
    (writers ? layout.writers : layout.readers).push_back(std::move(ep));
  });
}

bool in_partition(const EndpointInfo& e, std::string_view partition) {
  return std::find(e.partitions.begin(), e.partitions.end(), partition) != e.partitions.end();
}

}  // namespace

Result<std::vector<EntityLayout>> discover(const Participant& observer, Clock& clock,
                                           std::chrono::nanoseconds settle, std::string_view partition) {
  auto participants = builtin_reader(observer, DDS_BUILTIN_TOPIC_DCPSPARTICIPANT);
  auto publications = builtin_reader(observer, DDS_BUILTIN_TOPIC_DCPSPUBLICATION);
  auto subscriptions = builtin_reader(observer, DDS_BUILTIN_TOPIC_DCPSSUBSCRIPTION);
  for (const auto* r : {&participants, &publications, &subscriptions}) {
    if (!r->ok()) {
      return r->error();
    }
  }
  clock.sleep_until(clock.now() + settle);

  std::map<std::string, EntityLayout> by_key;
  SF_TRY(read_all(participants->get(), [&](const void* s, const SampleInfo& info) {
    if (!info.valid_data || info.instance_state != InstanceState::Alive) {
      return;
    }
    const auto* p = static_cast<const dds_builtintopic_participant_t*>(s);
    const auto key = participant_prefix(hex_key(p->key));
    by_key[key].participant = name_of(p->qos);
  }));
  SF_TRY(read_endpoints(publications->get(), by_key, true));
  SF_TRY(read_endpoints(subscriptions->get(), by_key, false));

  std::vector<EntityLayout> out;
  for (auto& [key, layout] : by_key) {
    layout.key = key;
    layout.domain = observer.domain_id();
    if (!partition.empty()) {
      std::erase_if(layout.readers, [&](const EndpointInfo& e) { return !in_partition(e, partition); });
      std::erase_if(layout.writers, [&](const EndpointInfo& e) { return !in_partition(e, partition); });
      if (layout.readers.empty() && layout.writers.empty()) {
        continue;
      }
    }
    out.push_back(std::move(layout));
  }
  return out;
}

}  // namespace sf::dds
