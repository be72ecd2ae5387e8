#include "sf/dds/writer.hpp"

#include <fmt/format.h>

namespace sf::dds {

Result<WriterBase> WriterBase::create_raw(const Participant& participant, dds_entity_t topic,
                                          std::string topic_name, const Qos& qos, Executor* executor,
                                          WriterListeners listeners) {
  std::shared_ptr<detail::ListenerCore> core;
  if (listeners.on_publication_matched || listeners.on_liveliness_lost ||
      listeners.on_offered_deadline_missed) {
    if (executor == nullptr) {
      return Error{Errc::invalid_argument,
                   fmt::format("writer of {}: listeners need an executor", topic_name)};
    }
    core = std::make_shared<detail::ListenerCore>(*executor);
    core->writer = std::move(listeners);
  }
  dds_listener_t* l = detail::make_writer_listener(core.get());
  const dds_entity_t w = dds_create_writer(participant.publisher(), topic, qos.get(), l);
  if (l != nullptr) {
    dds_delete_listener(l);
  }
  if (w < 0) {
    return dds_error(w, fmt::format("dds_create_writer({})", topic_name));
  }
  if (core) {
    core->entity.store(w);
  }
  // As the writer got it (the publisher's QoS may set it); true, the
  // policy's default, if it cannot be read.
  bool autodispose = true;
  if (Qos effective; dds_get_qos(w, effective.get()) == DDS_RETCODE_OK) {
    dds_qget_writer_data_lifecycle(effective.get(), &autodispose);
  }
  return WriterBase{Entity{w}, std::move(core), std::move(topic_name), autodispose};
}

WriterBase& WriterBase::operator=(WriterBase&& other) noexcept {
  if (this != &other) {
    close();
    entity_ = std::move(other.entity_);
    core_ = std::move(other.core_);
    topic_name_ = std::move(other.topic_name_);
    autodispose_ = other.autodispose_;
  }
  return *this;
}

WriterBase::~WriterBase() {
  close();
}

void WriterBase::close() {
  if (entity_.get() > 0) {
    flush();  // nothing left in the batch is lost with the writer
  }
  entity_.reset();
  if (core_) {
    core_->close();
    core_.reset();
  }
}

void WriterBase::flush() const {
  dds_write_flush(handle());
}

// With write batching, a message stays in the writer's batch until dds_write_flush (dds.h): it
// is flushed even when Cyclone refused it, so nothing queued before it is held back.
Status WriterBase::finish(dds_return_t rc, Send send, std::string_view call) const {
  if (send == Send::now) {
    flush();
  }
  if (rc < 0) {
    return dds_error(rc, fmt::format("{}({})", call, topic_name_));
  }
  return {};
}

Status WriterBase::write_raw(const void* sample) const {
  return finish(dds_write(handle(), sample), Send::now, "dds_write");
}

Status WriterBase::dispose_raw(const void* sample, Send send) const {
  return finish(dds_dispose(handle(), sample), send, "dds_dispose");
}

Status WriterBase::unregister_raw(const void* sample, Send send) const {
  return finish(dds_unregister_instance(handle(), sample), send, "dds_unregister_instance");
}

Result<MatchedStatus> WriterBase::publication_matched() const {
  dds_publication_matched_status_t s{};
  if (const auto rc = dds_get_publication_matched_status(handle(), &s); rc < 0) {
    return dds_error(rc, fmt::format("publication matched status of {}", topic_name_));
  }
  return MatchedStatus{s.total_count, s.current_count, s.current_count_change, s.last_subscription_handle};
}

Result<Qos> WriterBase::qos() const {
  Qos q;
  if (const auto rc = dds_get_qos(handle(), q.get()); rc < 0) {
    return dds_error(rc, fmt::format("QoS of writer {}", topic_name_));
  }
  return q;
}

Status WriterBase::assert_liveliness() const {
  if (const auto rc = dds_assert_liveliness(handle()); rc < 0) {
    return dds_error(rc, fmt::format("dds_assert_liveliness({})", topic_name_));
  }
  return {};
}

}  // namespace sf::dds
