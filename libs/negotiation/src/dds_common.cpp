#include "dds_common.hpp"

namespace sf::negotiation::detail {

namespace {

dds::QosBuilder writer_qos_builder(const DdsSettings& s) {
  dds::QosBuilder b;
  b.reliable(std::chrono::seconds{1}).durability(dds::Durability::TransientLocal).keep_last(s.history_depth);
  return b;
}

}  // namespace

dds::Qos writer_qos(const DdsSettings& s) {
  return writer_qos_builder(s).build();
}

dds::Qos bid_writer_qos(const DdsSettings& s) {
  return writer_qos_builder(s).liveliness(dds::Liveliness::ManualByTopic, s.liveliness_lease).build();
}

dds::Qos reader_qos(const DdsSettings& s) {
  return dds::QosBuilder{}
      .reliable()
      .durability(dds::Durability::TransientLocal)
      .keep_last(s.history_depth)
      .build();
}

Result<dds::Participant> join(const DdsSettings& s, dds::DomainId domain, const std::string& name) {
  auto xml = dds::cyclone_config_xml(s.network);
  if (!xml) {
    return xml.error();
  }
  return dds::Participant::create(domain, {*xml, name, s.partition});
}

void OpenConversations::opened(std::uint64_t hash, const std::string& conversation, const log::Logger& log) {
  auto [it, added] = open_.try_emplace(hash, conversation);
  if (!added && it->second != conversation) {
    // Two conversations alive with one key hash share an instance (see the IDL): the newer one
    // now owns it, and the older one's end will not be reported.
    log->warn("{}: conversations {} and {} share instance key {:#x}", topic_, it->second, conversation, hash);
    it->second = conversation;
  }
}

std::optional<std::string> OpenConversations::closed(std::uint64_t hash) {
  auto node = open_.extract(hash);
  if (node.empty()) {
    return std::nullopt;
  }
  return std::move(node.mapped());
}

void log_status(const log::Logger& log, const Status& st, std::string_view what) {
  if (!st) {
    log->debug("{}: {}", what, st.error().describe());
  }
}

}  // namespace sf::negotiation::detail

namespace sf::negotiation {

DdsSettings dds_settings(dds::DomainId machining_domain, dds::DomainId conveying_domain,
                         std::string partition, const std::string& interface,
                         std::chrono::nanoseconds lease) {
  DdsSettings s;
  s.machining_domain = machining_domain;
  s.conveying_domain = conveying_domain;
  s.partition = std::move(partition);
  s.network = interface == "lo" ? dds::loopback_network() : dds::interface_network(interface);
  s.liveliness_lease = lease;
  return s;
}

}  // namespace sf::negotiation
