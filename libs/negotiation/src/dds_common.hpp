// Shared by the DDS transports (dds_product.cpp, dds_machine.cpp,
// dds_conveyor.cpp): the topic types, the endpoint QoS and small helpers.
#pragma once

#include <optional>
#include <string>

#include "cnp_messages.h"
#include "dds_codec.hpp"
#include "sf/core/log.hpp"
#include "sf/dds/qos.hpp"
#include "sf/dds/reader.hpp"
#include "sf/dds/topic.hpp"
#include "sf/dds/writer.hpp"
#include "sf/negotiation/dds_transport.hpp"

SF_DDS_TOPIC_TYPE(sf_cnp_Announce);
SF_DDS_TOPIC_TYPE(sf_cnp_ContractorMessage);
SF_DDS_TOPIC_TYPE(sf_cnp_ManagerMessage);
SF_DDS_TOPIC_TYPE(sf_cnp_TransportRequest);
SF_DDS_TOPIC_TYPE(sf_cnp_TransportInform);

namespace sf::negotiation::detail {

template <typename T>
using Opt = std::optional<T>;

// RELIABLE, TRANSIENT_LOCAL, KEEP_LAST(depth); writers assert AUTOMATIC liveliness.
dds::Qos writer_qos(const DdsSettings& s);
dds::Qos reader_qos(const DdsSettings& s);
// A participant of `domain` with the settings' network configuration and partition.
Result<dds::Participant> join(const DdsSettings& s, dds::DomainId domain, const std::string& name);
// Failures to dispose are not the caller's problem: logged at debug level.
void log_status(const log::Logger& log, const Status& st, std::string_view what);

}  // namespace sf::negotiation::detail

// Creates `opt` from a Result, or returns its error from the enclosing function.
#define SF_EMPLACE(opt, expr)                      \
  do {                                             \
    auto sf_emplace_result_ = (expr);              \
    if (!sf_emplace_result_) {                     \
      return sf_emplace_result_.error();           \
    }                                              \
    (opt).emplace(std::move(*sf_emplace_result_)); \
  } while (false)
