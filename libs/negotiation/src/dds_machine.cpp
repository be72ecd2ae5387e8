// Machine side of the DDS transport: per supported operation reader
// OPx_ANNOUNCE, reader OPx_AWARD, writer OPx_BID.
#include <map>

#include <fmt/format.h>

#include "dds_common.hpp"

namespace sf::negotiation {

using detail::bid_writer_qos;
using detail::join;
using detail::log_status;
using detail::Opt;
using detail::reader_qos;

// ============================================================================
// Machine: per operation reader ANNOUNCE, reader AWARD, writer BID.
// ============================================================================

struct MachineOp {
  std::string operation;
  Opt<dds::Topic<sf_cnp_Announce>> announce_topic;
  Opt<dds::Topic<sf_cnp_ContractorMessage>> bid_topic;
  Opt<dds::Topic<sf_cnp_ManagerMessage>> award_topic;
  Opt<detail::EndingWriter<sf_cnp_ContractorMessage>> bid;
  Opt<dds::Reader<sf_cnp_Announce>> announce;
  Opt<dds::Reader<sf_cnp_ManagerMessage>> award;
  Opt<detail::OpenConversations> announces;
  Opt<detail::OpenConversations> awards;
  Clock::time_point asserted_at{};  // the BID writer's last write or liveliness assertion
};

struct MachineEndpoints::Impl {
  log::Logger log = log::get("negotiation");
  const Clock* clock = nullptr;
  ContractorInbox* inbox = nullptr;
  std::string name;
  // A third of the lease: two assertions may be late or lost before the products give up.
  std::chrono::nanoseconds assert_every{};
  Opt<dds::Participant> participant;
  std::map<std::string, std::unique_ptr<MachineOp>> ops;

  Status add_operation(const DdsSettings& s, const std::string& op, dds::Executor& ex);
  void on_announce(MachineOp& op, const sf_cnp_Announce& sample, const dds::SampleInfo& info);
  void on_award(MachineOp& op, const sf_cnp_ManagerMessage& sample, const dds::SampleInfo& info);
};

Status MachineEndpoints::Impl::add_operation(const DdsSettings& s, const std::string& name_of_op,
                                             dds::Executor& ex) {
  SF_TRY(validate_operation(name_of_op));
  auto op = std::make_unique<MachineOp>();
  op->operation = name_of_op;
  op->announces.emplace(announce_topic(name_of_op));
  op->awards.emplace(award_topic(name_of_op));
  MachineOp* raw = op.get();
  const auto& p = *participant;
  SF_EMPLACE(op->announce_topic, dds::Topic<sf_cnp_Announce>::create(p, announce_topic(name_of_op)));
  SF_EMPLACE(op->bid_topic, dds::Topic<sf_cnp_ContractorMessage>::create(p, bid_topic(name_of_op)));
  SF_EMPLACE(op->award_topic, dds::Topic<sf_cnp_ManagerMessage>::create(p, award_topic(name_of_op)));
  // Every machine of OPx reads OPx_AWARD (the paper's layout), but only the addressee acts on an
  // award or cancel: the others' are dropped inside Cyclone, with no instance, listener call or
  // decoding for them (docs/performance.md). Their ends still arrive: Cyclone does not filter
  // key-only samples, and the reader never saw their conversation, so they close nothing.
  SF_TRY(op->award_topic->set_filter(
      [this](const sf_cnp_ManagerMessage& m) { return codec::addressed_to(m, name); }));
  SF_EMPLACE(op->bid, dds::Writer<sf_cnp_ContractorMessage>::create(p, *op->bid_topic, bid_writer_qos(s)),
             *clock);
  op->asserted_at = clock->now();
  SF_EMPLACE(op->announce, dds::Reader<sf_cnp_Announce>::create(
                               p, *op->announce_topic, reader_qos(s), &ex,
                               [this, raw](const sf_cnp_Announce& m, const dds::SampleInfo& i) {
                                 on_announce(*raw, m, i);
                               }));
  SF_EMPLACE(op->award, dds::Reader<sf_cnp_ManagerMessage>::create(
                            p, *op->award_topic, reader_qos(s), &ex,
                            [this, raw](const sf_cnp_ManagerMessage& m, const dds::SampleInfo& i) {
                              on_award(*raw, m, i);
                            }));
  ops.emplace(name_of_op, std::move(op));
  return {};
}

void MachineEndpoints::Impl::on_announce(MachineOp& op, const sf_cnp_Announce& sample,
                                         const dds::SampleInfo& info) {
  if (inbox == nullptr) {
    return;
  }
  auto s = detail::read_conversation<Announce>(*op.announces, sample, info, log);
  if (s.message && s.alive) {
    inbox->on_announce(*s.message);
  }
  if (s.ended) {
    inbox->on_conversation_closed(op.operation, *s.ended);
  }
}

void MachineEndpoints::Impl::on_award(MachineOp& op, const sf_cnp_ManagerMessage& sample,
                                      const dds::SampleInfo& info) {
  if (inbox == nullptr) {
    return;
  }
  auto s = detail::read_conversation<ManagerMessage>(*op.awards, sample, info, log);
  if (s.message) {
    inbox->on_manager_message(*s.message);
  }
  if (s.ended) {
    inbox->on_conversation_closed(op.operation, *s.ended);
  }
}

MachineEndpoints::MachineEndpoints(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
MachineEndpoints::~MachineEndpoints() = default;

Result<std::unique_ptr<MachineEndpoints>> MachineEndpoints::create(const DdsSettings& settings,
                                                                   const std::string& name,
                                                                   const std::vector<std::string>& operations,
                                                                   dds::Executor& executor,
                                                                   const Clock& clock) {
  SF_TRY(validate_name("machine", name));
  auto impl = std::make_unique<Impl>();
  impl->clock = &clock;
  impl->name = name;
  impl->assert_every = settings.liveliness_lease / 3;
  SF_EMPLACE(impl->participant, join(settings, settings.machining_domain, "machine/" + name));
  for (const auto& op : operations) {
    SF_TRY(impl->add_operation(settings, op, executor));
  }
  return std::unique_ptr<MachineEndpoints>(new MachineEndpoints(std::move(impl)));
}

void MachineEndpoints::bind(ContractorInbox& inbox) {
  impl_->inbox = &inbox;
}

Status MachineEndpoints::send(const ContractorMessage& m) {
  auto it = impl_->ops.find(m.operation);
  if (it == impl_->ops.end()) {
    return Error{Errc::not_found,
                 fmt::format("no {} topic: operation not supported", bid_topic(m.operation))};
  }
  codec::ParamStorage storage;
  auto sample = codec::encode(m, storage);
  if (!sample) {
    return sample.error();
  }
  MachineOp& op = *it->second;
  SF_TRY(op.bid->write(*sample));
  op.asserted_at = impl_->clock->now();  // a write asserts a MANUAL_BY_TOPIC writer's liveliness
  return {};
}

void MachineEndpoints::assert_liveliness() {
  const auto now = impl_->clock->now();
  for (auto& [name, op] : impl_->ops) {
    if (now - op->asserted_at >= impl_->assert_every) {
      op->asserted_at = now;
      log_status(impl_->log, op->bid->writer().assert_liveliness(), "assert liveliness");
    }
  }
}

std::optional<Clock::time_point> MachineEndpoints::liveliness_due() const {
  std::optional<Clock::time_point> due;
  for (const auto& [name, op] : impl_->ops) {
    due = earliest(due, op->asserted_at + impl_->assert_every);
  }
  return due;
}

// The ends leave in batches (EndingWriter).
void MachineEndpoints::close(const std::string& operation, const std::string& conversation) {
  auto it = impl_->ops.find(operation);
  if (it != impl_->ops.end()) {
    log_status(impl_->log, it->second->bid->end_later(codec::contractor_key(conversation, impl_->name)),
               "dispose");
  }
}

void MachineEndpoints::flush_ended() {
  const auto now = impl_->clock->now();
  for (auto& [name, op] : impl_->ops) {
    log_status(impl_->log, op->bid->flush_ended(now), "dispose");
  }
}

std::optional<Clock::time_point> MachineEndpoints::ends_due() const {
  std::optional<Clock::time_point> due;
  for (const auto& [name, op] : impl_->ops) {
    due = earliest(due, op->bid->ends_due());
  }
  return due;
}

const dds::Participant& MachineEndpoints::participant() const {
  return *impl_->participant;
}

std::size_t MachineEndpoints::managers(const std::string& operation) const {
  auto it = impl_->ops.find(operation);
  if (it == impl_->ops.end()) {
    return 0;
  }
  auto m = it->second->bid->writer().publication_matched();
  return m ? m->current_count : 0;
}

}  // namespace sf::negotiation
