// Product side of the DDS transport: per required operation writer OPx_ANNOUNCE,
// writer OPx_AWARD, reader OPx_BID; writer REQUEST and reader INFORM.
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
// Product: per operation writer ANNOUNCE, writer AWARD, reader BID; REQUEST/INFORM.
// ============================================================================

struct ProductOp {
  std::string operation;
  Opt<dds::Topic<sf_cnp_Announce>> announce_topic;
  Opt<dds::Topic<sf_cnp_ContractorMessage>> bid_topic;
  Opt<dds::Topic<sf_cnp_ManagerMessage>> award_topic;
  Opt<detail::EndingWriter<sf_cnp_Announce>> announce;
  Opt<detail::EndingWriter<sf_cnp_ManagerMessage>> award;
  Opt<dds::Reader<sf_cnp_ContractorMessage>> bid;
  std::map<dds_instance_handle_t, std::string> bidders;  // OPx_BID writer → contractor
};

struct ProductEndpoints::Impl {
  log::Logger log = log::get("negotiation");
  const Clock* clock = nullptr;
  ManagerInbox* inbox = nullptr;
  RouteInbox* route_inbox = nullptr;
  // Declared first, destroyed last: the participants outlive their endpoints.
  Opt<dds::Participant> machining;
  Opt<dds::Participant> conveying;
  std::map<std::string, std::unique_ptr<ProductOp>> ops;
  Opt<dds::Topic<sf_cnp_TransportRequest>> request_topic;
  Opt<dds::Topic<sf_cnp_TransportInform>> inform_topic;
  Opt<dds::Writer<sf_cnp_TransportRequest>> request;
  Opt<dds::Reader<sf_cnp_TransportInform>> inform;

  Status add_operation(const DdsSettings& s, const std::string& op, dds::Executor& ex);
  Status add_conveying(const DdsSettings& s, dds::Executor& ex);
  void on_bid(ProductOp& op, const sf_cnp_ContractorMessage& sample, const dds::SampleInfo& info);
  void on_liveliness(ProductOp& op, const dds::LivelinessChangedStatus& status);
  void on_inform(const sf_cnp_TransportInform& sample, const dds::SampleInfo& info);
  ProductOp* find(const std::string& operation) const {
    auto it = ops.find(operation);
    return it == ops.end() ? nullptr : it->second.get();
  }
};

Status ProductEndpoints::Impl::add_operation(const DdsSettings& s, const std::string& name,
                                             dds::Executor& ex) {
  SF_TRY(validate_operation(name));
  auto op = std::make_unique<ProductOp>();
  op->operation = name;
  ProductOp* raw = op.get();
  const auto& p = *machining;
  SF_EMPLACE(op->announce_topic, dds::Topic<sf_cnp_Announce>::create(p, announce_topic(name)));
  SF_EMPLACE(op->bid_topic, dds::Topic<sf_cnp_ContractorMessage>::create(p, bid_topic(name)));
  SF_EMPLACE(op->award_topic, dds::Topic<sf_cnp_ManagerMessage>::create(p, award_topic(name)));
  SF_EMPLACE(op->announce, dds::Writer<sf_cnp_Announce>::create(p, *op->announce_topic, writer_qos(s)),
             *clock);
  SF_EMPLACE(op->award, dds::Writer<sf_cnp_ManagerMessage>::create(p, *op->award_topic, writer_qos(s)),
             *clock);
  SF_EMPLACE(
      op->bid,
      dds::Reader<sf_cnp_ContractorMessage>::create(
          p, *op->bid_topic, reader_qos(s), &ex,
          [this, raw](const sf_cnp_ContractorMessage& m, const dds::SampleInfo& i) { on_bid(*raw, m, i); },
          dds::ReaderListeners{
              {}, [this, raw](const dds::LivelinessChangedStatus& st) { on_liveliness(*raw, st); }, {}}));
  ops.emplace(name, std::move(op));
  return {};
}

Status ProductEndpoints::Impl::add_conveying(const DdsSettings& s, dds::Executor& ex) {
  const auto& p = *conveying;
  SF_EMPLACE(request_topic, dds::Topic<sf_cnp_TransportRequest>::create(p, std::string{kRequestTopic}));
  SF_EMPLACE(inform_topic, dds::Topic<sf_cnp_TransportInform>::create(p, std::string{kInformTopic}));
  SF_EMPLACE(request, dds::Writer<sf_cnp_TransportRequest>::create(p, *request_topic, writer_qos(s)));
  SF_EMPLACE(inform,
             dds::Reader<sf_cnp_TransportInform>::create(
                 p, *inform_topic, reader_qos(s), &ex,
                 [this](const sf_cnp_TransportInform& m, const dds::SampleInfo& i) { on_inform(m, i); }));
  return {};
}

void ProductEndpoints::Impl::on_bid(ProductOp& op, const sf_cnp_ContractorMessage& sample,
                                    const dds::SampleInfo& info) {
  if (!info.valid_data) {
    return;  // a contractor let go of its instance
  }
  auto m = codec::decode(sample);
  if (!m) {
    log->warn("{}: dropped a malformed sample: {}", bid_topic(op.operation), m.error().describe());
    return;
  }
  op.bidders[info.publication_handle] = m->contractor;
  if (inbox != nullptr) {
    inbox->on_contractor_message(*m);
  }
}

void ProductEndpoints::Impl::on_liveliness(ProductOp& op, const dds::LivelinessChangedStatus& st) {
  // alive_count down: the writer stopped asserting liveliness or went away; up: a writer that
  // had lost it asserts it again (or a new one matched, unknown until it bids).
  if (st.alive_count_change == 0) {
    return;
  }
  auto it = op.bidders.find(st.last_publication_handle);
  if (it == op.bidders.end()) {
    return;  // a contractor that never spoke to us
  }
  if (st.alive_count_change > 0) {
    log->info("{}: contractor {} is alive again", bid_topic(op.operation), it->second);
    if (inbox != nullptr) {
      inbox->on_contractor_alive(op.operation, it->second);
    }
    return;
  }
  log->info("{}: contractor {} lost liveliness", bid_topic(op.operation), it->second);
  if (inbox != nullptr) {
    inbox->on_contractor_lost(op.operation, it->second);
  }
}

void ProductEndpoints::Impl::on_inform(const sf_cnp_TransportInform& sample, const dds::SampleInfo& info) {
  if (!info.valid_data) {
    return;
  }
  auto m = codec::decode(sample);
  if (!m) {
    log->warn("{}: dropped a malformed sample: {}", kInformTopic, m.error().describe());
    return;
  }
  if (route_inbox != nullptr) {
    route_inbox->on_inform(*m);
  }
}

ProductEndpoints::ProductEndpoints(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
ProductEndpoints::~ProductEndpoints() = default;

Result<std::unique_ptr<ProductEndpoints>> ProductEndpoints::create(const DdsSettings& settings,
                                                                   const std::string& name,
                                                                   const std::vector<std::string>& operations,
                                                                   dds::Executor& executor,
                                                                   const Clock& clock, bool conveying) {
  SF_TRY(validate_name("product", name));
  auto impl = std::make_unique<Impl>();
  impl->clock = &clock;
  SF_EMPLACE(impl->machining, join(settings, settings.machining_domain, "product/" + name));
  for (const auto& op : operations) {
    SF_TRY(impl->add_operation(settings, op, executor));
  }
  if (conveying) {
    SF_EMPLACE(impl->conveying, join(settings, settings.conveying_domain, "product/" + name));
    SF_TRY(impl->add_conveying(settings, executor));
  }
  return std::unique_ptr<ProductEndpoints>(new ProductEndpoints(std::move(impl)));
}

void ProductEndpoints::bind(ManagerInbox& inbox) {
  impl_->inbox = &inbox;
}
void ProductEndpoints::bind(RouteInbox& inbox) {
  impl_->route_inbox = &inbox;
}

Status ProductEndpoints::announce(const Announce& a) {
  ProductOp* op = impl_->find(a.operation);
  if (op == nullptr) {
    return Error{Errc::not_found,
                 fmt::format("no {} topic: operation not declared", announce_topic(a.operation))};
  }
  codec::ParamStorage storage;
  auto sample = codec::encode(a, storage);
  if (!sample) {
    return sample.error();
  }
  return op->announce->write(*sample);
}

Status ProductEndpoints::send(const ManagerMessage& m) {
  ProductOp* op = impl_->find(m.operation);
  if (op == nullptr) {
    return Error{Errc::not_found,
                 fmt::format("no {} topic: operation not declared", award_topic(m.operation))};
  }
  codec::ParamStorage storage;
  auto sample = codec::encode(m, storage);
  if (!sample) {
    return sample.error();
  }
  return op->award->write(*sample);
}

// The ends leave in batches (EndingWriter).
void ProductEndpoints::close(const std::string& operation, const std::string& conversation) {
  if (ProductOp* op = impl_->find(operation)) {
    log_status(impl_->log, op->announce->end_later(codec::announce_key(conversation)), "dispose");
    log_status(impl_->log, op->award->end_later(codec::manager_key(conversation)), "dispose");
  }
}

void ProductEndpoints::flush_ended() {
  const auto now = impl_->clock->now();
  for (auto& [name, op] : impl_->ops) {
    log_status(impl_->log, op->announce->flush_ended(now), "dispose");
    log_status(impl_->log, op->award->flush_ended(now), "dispose");
  }
}

std::optional<Clock::time_point> ProductEndpoints::ends_due() const {
  std::optional<Clock::time_point> due;
  for (const auto& [name, op] : impl_->ops) {
    due = earliest(due, earliest(op->announce->ends_due(), op->award->ends_due()));
  }
  return due;
}

std::size_t ProductEndpoints::contractors(const std::string& operation) const {
  ProductOp* op = impl_->find(operation);
  if (op == nullptr) {
    return 0;
  }
  auto m = op->announce->writer().publication_matched();
  return m ? m->current_count : 0;
}

std::size_t ProductEndpoints::bidders(const std::string& operation) const {
  ProductOp* op = impl_->find(operation);
  if (op == nullptr) {
    return 0;
  }
  auto m = op->bid->subscription_matched();
  return m ? m->current_count : 0;
}

Status ProductEndpoints::request(const TransportRequest& r) {
  if (!impl_->request) {
    return Error{Errc::state, "this product does not negotiate routes (no ConveyingDomain participant)"};
  }
  auto sample = codec::encode(r);
  if (!sample) {
    return sample.error();
  }
  return impl_->request->write(*sample);
}

void ProductEndpoints::close(const std::string& conversation) {
  if (impl_->request) {
    log_status(impl_->log, impl_->request->dispose_and_unregister(codec::request_key(conversation)),
               "dispose");
  }
}

std::size_t ProductEndpoints::conveyors() const {
  if (!impl_->request) {
    return 0;
  }
  auto m = impl_->request->publication_matched();
  return m ? m->current_count : 0;
}

const dds::Participant& ProductEndpoints::machining() const {
  return *impl_->machining;
}
const dds::Participant* ProductEndpoints::conveying() const {
  return impl_->conveying ? &*impl_->conveying : nullptr;
}

}  // namespace sf::negotiation
