#include "sf/dds/reader.hpp"

#include <array>
#include <vector>

#include <fmt/format.h>

namespace sf::dds {
namespace {

InstanceState instance_state_of(dds_instance_state_t s) {
  switch (s) {
    case DDS_IST_NOT_ALIVE_DISPOSED:
      return InstanceState::Disposed;
    case DDS_IST_NOT_ALIVE_NO_WRITERS:
      return InstanceState::NoWriters;
    default:
      return InstanceState::Alive;
  }
}

SampleInfo sample_info_of(const dds_sample_info_t& i) {
  return SampleInfo{i.valid_data, instance_state_of(i.instance_state), i.instance_handle,
                    i.publication_handle, i.source_timestamp};
}

}  // namespace

Result<ReaderBase> ReaderBase::create_raw(const Participant& participant, dds_entity_t topic,
                                          std::string topic_name, const Qos& qos, Executor* executor,
                                          std::function<void(dds_entity_t)> on_data,
                                          ReaderListeners listeners) {
  std::shared_ptr<detail::ListenerCore> core;
  const bool wants_events = on_data || listeners.on_subscription_matched || listeners.on_liveliness_changed ||
                            listeners.on_requested_deadline_missed;
  if (wants_events) {
    if (executor == nullptr) {
      return Error{Errc::invalid_argument,
                   fmt::format("reader of {}: callbacks need an executor", topic_name)};
    }
    core = std::make_shared<detail::ListenerCore>(*executor);
    core->on_data = std::move(on_data);
    core->reader = std::move(listeners);
  }
  dds_listener_t* l = detail::make_reader_listener(core.get());
  const dds_entity_t r = dds_create_reader(participant.subscriber(), topic, qos.get(), l);
  if (l != nullptr) {
    dds_delete_listener(l);  // Cyclone copied it
  }
  if (r < 0) {
    return dds_error(r, fmt::format("dds_create_reader({})", topic_name));
  }
  if (core) {
    core->entity.store(r);
    // Data that arrived before the handle was known (transient-local history).
    core->post_data_available();
  }
  return ReaderBase{Entity{r}, std::move(core), std::move(topic_name)};
}

ReaderBase& ReaderBase::operator=(ReaderBase&& other) noexcept {
  if (this != &other) {
    close();
    entity_ = std::move(other.entity_);
    core_ = std::move(other.core_);
    topic_name_ = std::move(other.topic_name_);
  }
  return *this;
}

ReaderBase::~ReaderBase() {
  close();
}

void ReaderBase::close() {
  // dds_delete waits for listener callbacks in progress; closing the core
  // then turns tasks still queued on the executor into no-ops.
  entity_.reset();
  if (core_) {
    core_->close();
    core_.reset();
  }
}

Result<MatchedStatus> ReaderBase::subscription_matched() const {
  dds_subscription_matched_status_t s{};
  if (const auto rc = dds_get_subscription_matched_status(handle(), &s); rc < 0) {
    return dds_error(rc, fmt::format("subscription matched status of {}", topic_name_));
  }
  return MatchedStatus{s.total_count, s.current_count, s.current_count_change, s.last_publication_handle};
}

Result<LivelinessChangedStatus> ReaderBase::liveliness_changed() const {
  dds_liveliness_changed_status_t s{};
  if (const auto rc = dds_get_liveliness_changed_status(handle(), &s); rc < 0) {
    return dds_error(rc, fmt::format("liveliness changed status of {}", topic_name_));
  }
  return LivelinessChangedStatus{s.alive_count, s.not_alive_count, s.alive_count_change,
                                 s.not_alive_count_change, s.last_publication_handle};
}

Result<Qos> ReaderBase::qos() const {
  Qos q;
  if (const auto rc = dds_get_qos(handle(), q.get()); rc < 0) {
    return dds_error(rc, fmt::format("QoS of reader {}", topic_name_));
  }
  return q;
}

Result<std::size_t> ReaderBase::take_raw(dds_entity_t reader, std::size_t max, const RawSampleFn& fn) {
  constexpr std::size_t kMaxBatch = 256;
  max = std::min(max, kMaxBatch);
  // Left uninitialised: zeroing 256 sample infos (16 KiB) on every take was, with Cyclone zeroing
  // its loan buffer (see Reader::drain), a quarter of a busy reader thread's time. Cyclone reads
  // only samples[0] and fills as many entries as its loan holds, never more than `max` <=
  // kMaxBatch; only entries 0..n-1 are read here.
  std::array<void*, kMaxBatch> samples;            // NOLINT(cppcoreguidelines-pro-type-member-init)
  std::array<dds_sample_info_t, kMaxBatch> infos;  // NOLINT(cppcoreguidelines-pro-type-member-init)
  samples[0] = nullptr;                            // asks Cyclone to lend its own buffers
  const dds_return_t n = dds_take(reader, samples.data(), infos.data(), max, static_cast<std::uint32_t>(max));
  if (n < 0) {
    return dds_error(n, "dds_take");
  }
  const auto count = static_cast<std::size_t>(n);
  for (std::size_t i = 0; i < count; ++i) {
    fn(samples[i], sample_info_of(infos[i]));
  }
  if (count > 0) {
    (void)dds_return_loan(reader, samples.data(), n);
  }
  return count;
}

}  // namespace sf::dds
