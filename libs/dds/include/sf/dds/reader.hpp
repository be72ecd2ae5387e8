// Reader<T>: a DataReader (DDS 1.4 §2.2.2.5.3) of an idlc-generated type.
//
// With an Executor and a callback, every arriving sample (and every instance
// state change: dispose, unregister, writer lost) is taken and handed to the
// callback on the executor's thread. Samples are read through Cyclone's loans,
// so a callback gets a reference valid only during the call: copy what you keep.
// Destroying the reader stops deliveries, including tasks already queued.
#pragma once

#include <cstddef>
#include <functional>
#include <memory>
#include <string>

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

using RawSampleFn = std::function<void(const void* sample, const SampleInfo& info)>;

class ReaderBase {
 public:
  ReaderBase(ReaderBase&&) noexcept = default;
  ReaderBase& operator=(ReaderBase&&) noexcept;
  ~ReaderBase();

  [[nodiscard]] dds_entity_t handle() const { return entity_.get(); }
  [[nodiscard]] const std::string& topic_name() const { return topic_name_; }
  [[nodiscard]] Result<MatchedStatus> subscription_matched() const;
  [[nodiscard]] Result<LivelinessChangedStatus> liveliness_changed() const;
  [[nodiscard]] Result<Qos> qos() const;

  // Takes up to `max` samples, calling fn for each while the loan is held.
  static Result<std::size_t> take_raw(dds_entity_t reader, std::size_t max, const RawSampleFn& fn);

 protected:
  static Result<ReaderBase> create_raw(const Participant& participant, dds_entity_t topic,
                                       std::string topic_name, const Qos& qos, Executor* executor,
                                       std::function<void(dds_entity_t)> on_data, ReaderListeners listeners);

 private:
  ReaderBase(Entity entity, std::shared_ptr<detail::ListenerCore> core, std::string topic_name)
      : entity_(std::move(entity)), core_(std::move(core)), topic_name_(std::move(topic_name)) {}
  void close();

  Entity entity_;
  std::shared_ptr<detail::ListenerCore> core_;
  std::string topic_name_;
};

template <typename T>
class Reader : public ReaderBase {
 public:
  using Callback = std::function<void(const T& sample, const SampleInfo& info)>;

  // `executor` is needed for on_sample and for listeners; without them the
  // reader is polled with take().
  static Result<Reader> create(const Participant& participant, const Topic<T>& topic, const Qos& qos,
                               Executor* executor = nullptr, Callback on_sample = {},
                               ReaderListeners listeners = {}) {
    std::function<void(dds_entity_t)> on_data;
    if (on_sample) {
      on_data = [cb = std::move(on_sample)](dds_entity_t reader) { drain(reader, cb); };
    }
    auto base = create_raw(participant, topic.handle(), topic.name(), qos, executor, std::move(on_data),
                           std::move(listeners));
    if (!base) {
      return base.error();
    }
    return Reader{std::move(*base)};
  }

  // Takes up to `max` samples now; fn sees each (valid or not).
  Result<std::size_t> take(const Callback& fn, std::size_t max = 256) const {
    return take_raw(handle(), max,
                    [&fn](const void* s, const SampleInfo& info) { fn(*static_cast<const T*>(s), info); });
  }

 private:
  explicit Reader(ReaderBase&& base) : ReaderBase(std::move(base)) {}

  static void drain(dds_entity_t reader, const Callback& cb) {
    // Small: returning a loan zeroes all of Cyclone's loan buffer, which is as many samples as
    // the largest take asked for. A listener usually finds one or two samples.
    constexpr std::size_t kBatch = 8;
    for (;;) {
      auto n = take_raw(reader, kBatch, [&cb](const void* s, const SampleInfo& info) {
        cb(*static_cast<const T*>(s), info);
      });
      if (!n || *n < kBatch) {
        return;
      }
    }
  }
};

}  // namespace sf::dds
