#include "sf/dds/introspection.hpp"

#include <algorithm>
#include <array>

#include <fmt/format.h>

#include "sf/dds/qos.hpp"

namespace sf::dds {
namespace {

Result<std::vector<dds_entity_t>> children_of(dds_entity_t parent) {
  const dds_return_t n = dds_get_children(parent, nullptr, 0);
  if (n < 0) {
    return dds_error(n, "dds_get_children");
  }
  std::vector<dds_entity_t> out(static_cast<std::size_t>(n));
  if (n > 0) {
    const dds_return_t m = dds_get_children(parent, out.data(), out.size());
    if (m < 0) {
      return dds_error(m, "dds_get_children");
    }
    out.resize(std::min(out.size(), static_cast<std::size_t>(m)));
  }
  return out;
}

Result<EndpointInfo> endpoint_of(dds_entity_t endpoint, const std::string& partition) {
  const dds_entity_t topic = dds_get_topic(endpoint);
  if (topic < 0) {
    return dds_error(topic, "dds_get_topic");
  }
  std::array<char, 256> name{};
  std::array<char, 256> type{};
  if (const auto rc = dds_get_name(topic, name.data(), name.size()); rc < 0) {
    return dds_error(rc, "dds_get_name");
  }
  if (const auto rc = dds_get_type_name(topic, type.data(), type.size()); rc < 0) {
    return dds_error(rc, "dds_get_type_name");
  }
  EndpointInfo info{name.data(), type.data(), {}};
  if (!partition.empty()) {
    info.partitions.push_back(partition);
  }
  return info;
}

Status collect(dds_entity_t group, const std::string& partition, std::vector<EndpointInfo>& out) {
  auto children = children_of(group);
  if (!children) {
    return children.error();
  }
  for (const dds_entity_t e : *children) {
    auto info = endpoint_of(e, partition);
    if (!info) {
      return info.error();
    }
    out.push_back(std::move(*info));
  }
  return {};
}

std::vector<std::string> sorted_topics(const std::vector<EndpointInfo>& endpoints) {
  std::vector<std::string> out;
  out.reserve(endpoints.size());
  for (const auto& e : endpoints) {
    out.push_back(e.topic);
  }
  std::sort(out.begin(), out.end());
  return out;
}

std::string json_string(std::string_view s) {
  std::string out = "\"";
  for (const char c : s) {
    if (c == '"' || c == '\\') {
      out += '\\';
      out += c;
    } else if (static_cast<unsigned char>(c) < 0x20) {
      out += fmt::format("\\u{:04x}", static_cast<unsigned>(static_cast<unsigned char>(c)));
    } else {
      out += c;
    }
  }
  return out + "\"";
}

std::string json_endpoints(const std::vector<EndpointInfo>& endpoints) {
  std::string out = "[";
  for (std::size_t i = 0; i < endpoints.size(); ++i) {
    out += fmt::format("{}{{\"topic\":{},\"type\":{}}}", i == 0 ? "" : ",", json_string(endpoints[i].topic),
                       json_string(endpoints[i].type));
  }
  return out + "]";
}

}  // namespace

std::size_t EntityLayout::readers_on(std::string_view topic) const {
  return static_cast<std::size_t>(
      std::count_if(readers.begin(), readers.end(), [&](const EndpointInfo& e) { return e.topic == topic; }));
}

std::size_t EntityLayout::writers_on(std::string_view topic) const {
  return static_cast<std::size_t>(
      std::count_if(writers.begin(), writers.end(), [&](const EndpointInfo& e) { return e.topic == topic; }));
}

std::vector<std::string> EntityLayout::reader_topics() const {
  return sorted_topics(readers);
}
std::vector<std::string> EntityLayout::writer_topics() const {
  return sorted_topics(writers);
}

Result<EntityLayout> inspect(const Participant& participant) {
  EntityLayout layout;
  layout.participant = participant.name();
  layout.domain = participant.domain_id();
  dds_guid_t guid{};
  if (dds_get_guid(participant.handle(), &guid) == DDS_RETCODE_OK) {
    // The 12-byte GUID prefix (DDSI-RTPS 2.2 §8.2.4.3), as discover() reports it.
    for (std::size_t i = 0; i < 12; ++i) {
      layout.key += fmt::format("{:02x}", guid.v[i]);
    }
  }
  SF_TRY(collect(participant.publisher(), participant.partition(), layout.writers));
  SF_TRY(collect(participant.subscriber(), participant.partition(), layout.readers));
  return layout;
}

std::string to_json(const EntityLayout& layout) {
  return fmt::format("{{\"participant\":{},\"key\":{},\"domain\":{},\"readers\":{},\"writers\":{}}}",
                     json_string(layout.participant), json_string(layout.key), layout.domain,
                     json_endpoints(layout.readers), json_endpoints(layout.writers));
}

}  // namespace sf::dds
