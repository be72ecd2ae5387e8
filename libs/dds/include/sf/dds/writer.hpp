// Writer<T>: a DataWriter (DDS 1.4 §2.2.2.4.2) of an idlc-generated type, with
// the instance life cycle: write, dispose (the instance is gone for everyone),
// unregister (this writer stops updating it).
//
// Every write, dispose and unregister leaves at once, as a datagram of its
// own to every remote reader. end_instances puts many instance ends into one
// datagram with Cyclone's write batching (Internal/WriteBatch, on in
// cyclone_config_xml): a remote reader receives them with one wake-up instead
// of one each. Readers in this process see every operation at once.
#pragma once

#include <functional>
#include <memory>
#include <span>
#include <string>
#include <string_view>

#include <dds/dds.h>

#include "sf/core/result.hpp"
#include "sf/dds/entity.hpp"
#include "sf/dds/executor.hpp"
#include "sf/dds/listener.hpp"
#include "sf/dds/participant.hpp"
#include "sf/dds/qos.hpp"
#include "sf/dds/status.hpp"
#include "sf/dds/topic.hpp"

namespace sf::dds {

class WriterBase {
 public:
  WriterBase(WriterBase&&) noexcept = default;
  WriterBase& operator=(WriterBase&&) noexcept;
  ~WriterBase();

  [[nodiscard]] dds_entity_t handle() const { return entity_.get(); }
  [[nodiscard]] const std::string& topic_name() const { return topic_name_; }
  [[nodiscard]] Result<MatchedStatus> publication_matched() const;
  [[nodiscard]] Result<Qos> qos() const;
  // For MANUAL_BY_* liveliness: this writer is alive.
  Status assert_liveliness() const;
  // WRITER_DATA_LIFECYCLE.autodispose_unregistered_instances as created.
  [[nodiscard]] bool autodispose() const { return autodispose_; }

 protected:
  // Sends what waits in the writer's batch.
  void flush() const;
  static Result<WriterBase> create_raw(const Participant& participant, dds_entity_t topic,
                                       std::string topic_name, const Qos& qos, Executor* executor,
                                       WriterListeners listeners);
  // `later`: the message waits in the writer's batch for the next flush.
  enum class Send { now, later };
  Status write_raw(const void* sample) const;
  Status dispose_raw(const void* sample, Send send) const;
  Status unregister_raw(const void* sample, Send send) const;
  // The result of a write, dispose or unregister `call`, flushed when `send` is now.
  Status finish(dds_return_t rc, Send send, std::string_view call) const;

 private:
  WriterBase(Entity entity, std::shared_ptr<detail::ListenerCore> core, std::string topic_name,
             bool autodispose)
      : entity_(std::move(entity)),
        core_(std::move(core)),
        topic_name_(std::move(topic_name)),
        autodispose_(autodispose) {}
  void close();

  Entity entity_;
  std::shared_ptr<detail::ListenerCore> core_;
  std::string topic_name_;
  bool autodispose_ = true;
};

template <typename T>
class Writer : public WriterBase {
 public:
  static Result<Writer> create(const Participant& participant, const Topic<T>& topic, const Qos& qos,
                               Executor* executor = nullptr, WriterListeners listeners = {}) {
    auto base = create_raw(participant, topic.handle(), topic.name(), qos, executor, std::move(listeners));
    if (!base) {
      return base.error();
    }
    return Writer{std::move(*base)};
  }

  Status write(const T& sample) const { return write_raw(&sample); }
  // Only the key fields of `key` matter.
  Status dispose(const T& key) const { return dispose_raw(&key, Send::now); }
  Status unregister(const T& key) const { return unregister_raw(&key, Send::now); }
  // The end of a conversation: dispose, then let go of the instance so the
  // writer's history forgets it (TRANSIENT_LOCAL late joiners won't see it).
  // With autodispose_unregistered_instances (the default) the unregister
  // carries the dispose: one message to every reader instead of two.
  Status dispose_and_unregister(const T& key) const { return end_instance(key, Send::now); }
  // Ends the instances of `keys` with one flush: usually one datagram per reader (Cyclone may
  // send part of the batch early, e.g. when a write after an idle spell asks for an ack). The
  // first error is returned, after the other ends were still tried.
  Status end_instances(std::span<const T> keys) const {
    Status first_error;
    for (const T& key : keys) {
      if (auto st = end_instance(key, Send::later); !st && first_error) {
        first_error = st;
      }
    }
    flush();
    return first_error;
  }

 private:
  explicit Writer(WriterBase&& base) : WriterBase(std::move(base)) {}
  Status end_instance(const T& key, Send send) const {
    if (!autodispose()) {
      SF_TRY(dispose_raw(&key, send));
    }
    return unregister_raw(&key, send);
  }
};

}  // namespace sf::dds
