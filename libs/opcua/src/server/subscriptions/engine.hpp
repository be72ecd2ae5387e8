// The state of the subscriptions engine: monitored items, subscriptions, the sessions' Publish
// queues, and SubscriptionService::Impl that ties them together. Internal.
#pragma once

#include <algorithm>
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <deque>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <unordered_map>
#include <utility>
#include <vector>

#include "server/subscriptions/data_change.hpp"
#include "server/subscriptions/event_filter.hpp"
#include "sf/core/clock.hpp"
#include "sf/core/log.hpp"
#include "sf/opcua/server/subscriptions.hpp"
#include "sf/opcua/status_codes.hpp"

namespace sf::opcua::subs {

using time_point = Clock::time_point;

constexpr std::uint32_t kAttributeEventNotifier = 12;
constexpr std::uint32_t kAttributeValue = 13;
constexpr std::uint32_t kMaxAttributeId = 27;
// InfoType DataValue (bit 10) + Overflow (bit 7) of a StatusCode (OPC 10000-4 §7.34.1).
constexpr std::uint32_t kOverflowInfoBits = 0x0480;

Clock::duration milliseconds(double ms);

// One queued event: its fields; overflow_marker for the EventQueueOverflow event (§5.12.1.5).
struct QueuedEvent {
  Array<Variant> fields;
  bool overflow_marker = false;
};

struct MonitoredItem {
  std::uint32_t id = 0;
  ReadValueId item;
  MonitoringMode mode = MonitoringMode::Reporting;
  TimestampsToReturn timestamps = TimestampsToReturn::Both;
  std::uint32_t client_handle = 0;
  double sampling_interval_ms = 0;
  std::uint32_t queue_size = 1;
  bool discard_oldest = true;
  bool is_event = false;
  DataChangeSettings data_filter;
  std::shared_ptr<const CompiledEventFilter> event_filter;
  // The last sample that passed the filter, unstripped (what the next sample compares with).
  std::optional<DataValue> last;
  std::deque<DataValue> values;
  std::deque<QueuedEvent> events;
  time_point next_sample{};

  // The first sampling time after `now`: the next multiple of the sampling interval on the
  // clock, so that items with one interval are sampled together in one pass of the engine
  // instead of each at its own instant (a timer wake-up and a walk over the items per item).
  void schedule_first_sample(time_point now) {
    const auto interval = std::max(milliseconds(sampling_interval_ms), Clock::duration(1));
    next_sample = time_point((now.time_since_epoch() / interval + 1) * interval);
  }
  [[nodiscard]] bool reporting() const { return mode == MonitoringMode::Reporting; }
  [[nodiscard]] bool enabled() const { return mode != MonitoringMode::Disabled; }
  [[nodiscard]] std::size_t queued() const { return is_event ? events.size() : values.size(); }
  void clear_queue() {
    values.clear();
    events.clear();
    last.reset();
  }
};

// §5.12.1.5 queue handling for a data item: full queue → discard oldest (the next value gets
// the Overflow bit) or replace the newest (which gets the Overflow bit); no bit at size 1.
void enqueue_value(MonitoredItem& item, DataValue value);
// The same for events; the first discard adds an EventQueueOverflowEventType event (its fields
// made by `overflow_event`) to the queue, which stays until it is published.
void enqueue_event(MonitoredItem& item, Array<Variant> fields,
                   const std::function<Array<Variant>()>& overflow_event);
// A sample: reported when it passes the item's DataChangeFilter (or is the first one).
void offer_sample(MonitoredItem& item, const DataValue& sample, DateTime now);
// Drops the timestamps the item did not ask for; fills a missing server timestamp.
DataValue apply_timestamps(DataValue value, TimestampsToReturn timestamps, DateTime now);

struct Subscription {
  std::uint32_t id = 0;
  std::optional<SessionKey> session;  // none after close_session(delete=false)
  double publishing_interval_ms = 0;
  std::uint32_t max_keep_alive_count = 0;
  std::uint32_t lifetime_count = 0;
  std::uint32_t max_notifications = 0;
  bool publishing_enabled = true;
  std::uint8_t priority = 0;

  // §5.13.1.2 state variables. "Late": a publishing cycle had something to send (notifications
  // or a due keep-alive) but no Publish request was queued.
  bool late = false;
  time_point late_since{};
  bool message_sent = false;
  bool more_notifications = false;
  std::uint32_t empty_cycles = 0;      // publishing cycles since the last message
  std::uint32_t lifetime_counter = 0;  // cycles left without a Publish request
  time_point next_cycle{};
  std::uint32_t next_sequence_number = 1;
  std::deque<NotificationMessage> retransmission;
  std::map<std::uint32_t, MonitoredItem> items;
  std::uint32_t resume_from = 0;  // the item a message cut short by max_notifications stopped at

  [[nodiscard]] Clock::duration interval() const {
    return std::max(milliseconds(publishing_interval_ms), Clock::duration(std::chrono::milliseconds(1)));
  }
  [[nodiscard]] bool has_notifications() const;
  [[nodiscard]] time_point next_sample_due() const;
  void reset_lifetime() { lifetime_counter = lifetime_count; }
  // Sequence numbers count from 1 and skip 0 when they wrap (§7.21 NotificationMessage).
  std::uint32_t take_sequence_number();
  // Takes up to max_notifications queued notifications of reporting items into a message.
  NotificationMessage collect(DateTime now);
  // Keeps a sent message for Republish, the oldest dropped beyond `max`.
  void retain(const NotificationMessage& message, std::size_t max);
  [[nodiscard]] Array<std::uint32_t> available_sequence_numbers() const;
  // Removes an acknowledged message: Good or BadSequenceNumberUnknown.
  StatusCode acknowledge(std::uint32_t sequence_number);
};

// The revised parameters of CreateSubscription / ModifySubscription (§5.13.2.2, §5.13.3.2).
struct RevisedSubscription {
  double publishing_interval_ms = 0;
  std::uint32_t lifetime_count = 0;
  std::uint32_t max_keep_alive_count = 0;
  std::uint32_t max_notifications = 0;
};
RevisedSubscription revise_subscription(const SubscriptionLimits& limits, double interval_ms,
                                        std::uint32_t lifetime_count, std::uint32_t keep_alive_count,
                                        std::uint32_t max_notifications);

struct PendingPublish {
  std::uint32_t request_handle = 0;
  time_point deadline = time_point::max();
  Array<StatusCode> results;  // of the request's acknowledgements
  std::function<void(Message)> respond;
};

struct SessionState {
  std::deque<PendingPublish> publish_queue;
  std::set<std::uint32_t> subscriptions;
  // Final messages of expired subscriptions (StatusChangeNotification), sent before anything.
  std::deque<std::pair<std::uint32_t, NotificationMessage>> status_changes;
};

}  // namespace sf::opcua::subs

namespace sf::opcua {

struct SubscriptionService::Impl {
  Impl(const Clock& c, SubscriptionLimits l, SubscriptionCallbacks cb);

  const Clock& clock;
  SubscriptionLimits limits;
  SubscriptionCallbacks callbacks;
  log::Logger log;
  subs::TypeTree types;

  std::map<std::uint32_t, subs::Subscription> subscriptions;
  std::unordered_map<SessionKey, subs::SessionState> sessions;
  std::uint32_t next_subscription_id = 1;
  std::uint32_t next_item_id = 1;
  std::size_t item_count = 0;
  std::uint64_t internal_events = 0;  // EventQueueOverflow events made

  // Responses to Publish requests, delivered when the engine's state is consistent.
  std::vector<std::pair<std::function<void(Message)>, Message>> outbox;
  bool delivering = false;

  [[nodiscard]] DateTime utc_now() const;
  [[nodiscard]] ResponseHeader header(const RequestHeader& request, StatusCode result = {}) const;
  // The subscription `id` if `session` owns it.
  subs::Subscription* find(const SessionKey& session, std::uint32_t id);
  void delete_subscription(std::uint32_t id);

  // Publish machinery (publish.cpp).
  void deliver();
  void fault(subs::PendingPublish request, StatusCode code);
  void serve(const SessionKey& key);
  void fail_if_no_subscription(const SessionKey& key);
  void send(subs::Subscription& sub, bool notifications);
  void run_cycle(subs::Subscription& sub);
  void expire(subs::Subscription& sub);
  void sample_due(subs::Subscription& sub, time_point until, time_point now);
  void sample(subs::MonitoredItem& item);
  subs::SessionState* session_of(const subs::Subscription& sub);
};

}  // namespace sf::opcua
