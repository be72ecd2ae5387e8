#include "dds_common.hpp"

namespace sf::negotiation::detail {

dds::Qos writer_qos(const DdsSettings& s) {
  return dds::QosBuilder{}
      .reliable(std::chrono::seconds{1})
      .durability(dds::Durability::TransientLocal)
      .keep_last(s.history_depth)
      .liveliness(dds::Liveliness::Automatic, s.liveliness_lease)
      .build();
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

void log_status(const log::Logger& log, const Status& st, std::string_view what) {
  if (!st) {
    log->debug("{}: {}", what, st.error().describe());
  }
}

}  // namespace sf::negotiation::detail
