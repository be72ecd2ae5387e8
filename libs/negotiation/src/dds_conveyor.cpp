// Conveyor side of the DDS transport: reader REQUEST, writer INFORM.
#include <map>

#include <fmt/format.h>

#include "dds_common.hpp"

namespace sf::negotiation {

using detail::join;
using detail::log_status;
using detail::Opt;
using detail::reader_qos;
using detail::writer_qos;

// ============================================================================
// Conveyor: reader REQUEST, writer INFORM.
// ============================================================================

struct ConveyorEndpoints::Impl {
  log::Logger log = log::get("negotiation");
  ConveyorInbox* inbox = nullptr;
  std::string name;
  Opt<dds::Participant> participant;
  Opt<dds::Topic<sf_cnp_TransportRequest>> request_topic;
  Opt<dds::Topic<sf_cnp_TransportInform>> inform_topic;
  Opt<dds::Writer<sf_cnp_TransportInform>> inform;
  Opt<dds::Reader<sf_cnp_TransportRequest>> request;
  detail::OpenConversations requests{std::string{kRequestTopic}};

  void on_request(const sf_cnp_TransportRequest& sample, const dds::SampleInfo& info) {
    if (inbox == nullptr) {
      return;
    }
    auto s = detail::read_conversation<TransportRequest>(requests, sample, info, log);
    if (s.message && s.alive) {
      inbox->on_request(*s.message);
    }
    if (s.ended) {
      inbox->on_request_closed(*s.ended);
    }
  }
};

ConveyorEndpoints::ConveyorEndpoints(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
ConveyorEndpoints::~ConveyorEndpoints() = default;

Result<std::unique_ptr<ConveyorEndpoints>> ConveyorEndpoints::create(const DdsSettings& settings,
                                                                     const std::string& name,
                                                                     dds::Executor& executor) {
  SF_TRY(validate_name("conveyor", name));
  auto impl = std::make_unique<Impl>();
  impl->name = name;
  SF_EMPLACE(impl->participant, join(settings, settings.conveying_domain, "conveyor/" + name));
  const auto& p = *impl->participant;
  Impl* raw = impl.get();
  SF_EMPLACE(impl->request_topic, dds::Topic<sf_cnp_TransportRequest>::create(p, std::string{kRequestTopic}));
  SF_EMPLACE(impl->inform_topic, dds::Topic<sf_cnp_TransportInform>::create(p, std::string{kInformTopic}));
  SF_EMPLACE(impl->inform,
             dds::Writer<sf_cnp_TransportInform>::create(p, *impl->inform_topic, writer_qos(settings)));
  SF_EMPLACE(impl->request, dds::Reader<sf_cnp_TransportRequest>::create(
                                p, *impl->request_topic, reader_qos(settings), &executor,
                                [raw](const sf_cnp_TransportRequest& m, const dds::SampleInfo& i) {
                                  raw->on_request(m, i);
                                }));
  return std::unique_ptr<ConveyorEndpoints>(new ConveyorEndpoints(std::move(impl)));
}

void ConveyorEndpoints::bind(ConveyorInbox& inbox) {
  impl_->inbox = &inbox;
}

Status ConveyorEndpoints::inform(const TransportInform& i) {
  auto sample = codec::encode(i);
  if (!sample) {
    return sample.error();
  }
  return impl_->inform->write(*sample);
}

void ConveyorEndpoints::close(const std::string& conversation) {
  log_status(impl_->log, impl_->inform->dispose_and_unregister(codec::inform_key(conversation, impl_->name)),
             "dispose");
}

const dds::Participant& ConveyorEndpoints::participant() const {
  return *impl_->participant;
}

}  // namespace sf::negotiation
