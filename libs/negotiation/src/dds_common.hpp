// Shared by the DDS transports (dds_product.cpp, dds_machine.cpp,
// dds_conveyor.cpp): the topic types, the endpoint QoS and small helpers.
#pragma once

#include <chrono>
#include <optional>
#include <string>
#include <unordered_map>
#include <vector>

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

// RELIABLE, TRANSIENT_LOCAL, KEEP_LAST(depth).
dds::Qos writer_qos(const DdsSettings& s);
// writer_qos with MANUAL_BY_TOPIC liveliness and the settings' lease: the machine's OPx_BID
// writers, whose liveliness the products watch. Only the writer's own writes and assertions keep
// it alive, and they reach only its matched readers (the products). AUTOMATIC liveliness with a
// short lease instead makes Cyclone send participant messages (DDSI-RTPS 2.2 §8.4.13) to every
// participant of the domain, machines included, several times per lease: with 64 machines on one
// host that was 10 000 datagrams a second (docs/performance.md). It also kept a machine alive
// whose agent had stopped, as long as Cyclone's threads ran.
dds::Qos bid_writer_qos(const DdsSettings& s);
dds::Qos reader_qos(const DdsSettings& s);
// A participant of `domain` with the settings' network configuration and partition.
Result<dds::Participant> join(const DdsSettings& s, dds::DomainId domain, const std::string& name);
// Failures to dispose are not the caller's problem: logged at debug level.
void log_status(const log::Logger& log, const Status& st, std::string_view what);

// The conversations whose instances a reader holds, by key hash. An instance's end reaches the
// reader as a key-only sample, which carries the hash but not the conversation id (the IDL keys
// on hashes): the id is remembered from the instance's data until then. Entries live as long as
// their instances. Touched under the executor's strand only.
class OpenConversations {
 public:
  explicit OpenConversations(std::string topic) : topic_(std::move(topic)) {}
  [[nodiscard]] const std::string& topic() const { return topic_; }
  // A valid sample of an alive instance.
  void opened(std::uint64_t hash, const std::string& conversation, const log::Logger& log);
  // The instance ended: its conversation, if this reader saw it alive.
  std::optional<std::string> closed(std::uint64_t hash);
  [[nodiscard]] std::size_t size() const { return open_.size(); }

 private:
  std::string topic_;
  std::unordered_map<std::uint64_t, std::string> open_;
};

// What one sample of a conversation-keyed reader says: the message (valid data), and the
// conversation that ended when the instance is no longer alive (disposed, or its writers gone).
template <typename Message>
struct ConversationSample {
  std::optional<Message> message;
  bool alive = false;
  std::optional<std::string> ended;
};

// Decodes a sample (a malformed one is dropped with a log line) and keeps `open` up to date.
template <typename Message, typename Sample>
ConversationSample<Message> read_conversation(OpenConversations& open, const Sample& sample,
                                              const dds::SampleInfo& info, const log::Logger& log) {
  ConversationSample<Message> out;
  out.alive = info.instance_state == dds::InstanceState::Alive;
  if (info.valid_data) {
    auto m = codec::decode(sample);
    if (!m) {
      log->warn("{}: dropped a malformed sample: {}", open.topic(), m.error().describe());
      return out;
    }
    if (out.alive) {
      open.opened(sample.conversation_hash, m->conversation, log);
    }
    out.message = std::move(*m);
  }
  if (!out.alive) {
    out.ended = open.closed(sample.conversation_hash);
    if (!out.ended && out.message) {
      out.ended = out.message->conversation;
    }
  }
  return out;
}

// Conversation ends leave in batches. The end of a conversation's instance (an unregister, which
// carries the dispose) is a message to every reader of the topic; sent alone, it costs every
// reader's process a datagram and a wake-up, as much as the conversation's own ANNOUNCE or AWARD
// (with 4 contractor processes, 12 of a negotiation's 26 datagrams were ends). So an end waits,
// at most kEndDelay, and leaves with the other ends of its writer with one flush, usually one
// datagram (dds::Writer::end_instances), mostly off the path of the conversations still
// running (a full batch leaves from the handler that ended the conversation). The delay is
// long enough for many ends to gather where negotiations are slow because the contractor
// processes are many: with 64 of them a negotiation takes about 3 ms, and a 5 ms delay sent
// nearly every end alone (docs/performance.md).
inline constexpr std::chrono::milliseconds kEndDelay{50};
// A full batch leaves at once (3–5 KiB of keys: within one datagram).
inline constexpr std::size_t kMaxEndBatch = 32;

// A writer whose instance ends leave in batches: end_later queues, flush_ended sends once the
// oldest queued end waited kEndDelay (the agents call it on every turn of their loop and wake
// for ends_due()), a full batch or the destructor sends at once. Touched under the executor's
// strand only; the destructor runs outside it, so no handler may still run inline (the agents
// and the bench turn inline delivery off before their endpoints go).
template <typename T>
class EndingWriter {
 public:
  EndingWriter(dds::Writer<T> writer, const Clock& clock) : writer_(std::move(writer)), clock_(&clock) {}
  EndingWriter(EndingWriter&&) noexcept = default;
  EndingWriter& operator=(EndingWriter&&) = delete;
  EndingWriter(const EndingWriter&) = delete;
  EndingWriter& operator=(const EndingWriter&) = delete;
  ~EndingWriter() { (void)send_ended(); }

  Status write(const T& sample) const { return writer_.write(sample); }
  // Only the key fields of `key` matter.
  Status end_later(const T& key) {
    if (ended_.empty()) {
      since_ = clock_->now();
    }
    ended_.push_back(key);
    return ended_.size() >= kMaxEndBatch ? send_ended() : Status{};
  }
  Status flush_ended(Clock::time_point now) {
    if (ended_.empty() || now - since_ < kEndDelay) {
      return {};
    }
    return send_ended();
  }
  // When flush_ended will send the queued ends; nothing when none waits.
  [[nodiscard]] std::optional<Clock::time_point> ends_due() const {
    if (ended_.empty()) {
      return std::nullopt;
    }
    return since_ + kEndDelay;
  }
  [[nodiscard]] std::size_t waiting() const { return ended_.size(); }
  [[nodiscard]] const dds::Writer<T>& writer() const { return writer_; }

 private:
  Status send_ended() {
    if (ended_.empty()) {
      return {};
    }
    auto st = writer_.end_instances(ended_);
    ended_.clear();
    return st;
  }

  dds::Writer<T> writer_;
  const Clock* clock_;
  std::vector<T> ended_;  // keys
  Clock::time_point since_{};
};

}  // namespace sf::negotiation::detail

// Creates `opt` from a Result, or returns its error from the enclosing function.
#define SF_EMPLACE(opt, expr, ...)                                            \
  do {                                                                        \
    auto sf_emplace_result_ = (expr);                                         \
    if (!sf_emplace_result_) {                                                \
      return sf_emplace_result_.error();                                      \
    }                                                                         \
    (opt).emplace(std::move(*sf_emplace_result_) __VA_OPT__(, ) __VA_ARGS__); \
  } while (false)
