// The server's subscriptions engine: the Subscription service set (OPC 10000-4 §5.13), the
// MonitoredItem service set (§5.12), MonitoringParameters (§7.16 in v1.04 / §7.21 in v1.05),
// the data-change and event filters (§7.17 / §7.22) and the events of BaseEventType.
// Section numbers in this module are those of OPC 10000-4 v1.04 unless stated otherwise.
//
// Pure logic: no I/O, no address space. The engine reads attributes, EURanges and the type
// hierarchy through SubscriptionCallbacks and reads time from an injected Clock, so tests drive
// it with a ManualClock. The server calls tick() from a timer armed at next_due().
//
// Not thread-safe: call every member from one thread (the server's loop). Publish responses
// are delivered through the `respond` callbacks after the engine's state is consistent, so a
// callback may call back into the engine (e.g. queue the next Publish).
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>

#include "sf/core/clock.hpp"
#include "sf/opcua/messages.hpp"
#include "sf/opcua/types.hpp"

namespace sf::opcua {

struct SubscriptionLimits {
  std::size_t max_subscriptions_per_session = 100;
  std::size_t max_subscriptions = 1000;
  std::size_t max_monitored_items_per_subscription = 10'000;
  std::size_t max_monitored_items = 100'000;
  // Array length of one request (itemsToCreate, subscriptionIds, ...): BadTooManyOperations.
  std::size_t max_operations_per_request = 10'000;
  double min_publishing_interval_ms = 10;
  double max_publishing_interval_ms = 3'600'000;
  // 0 ("fastest practical rate") is revised to the minimum.
  double min_sampling_interval_ms = 10;
  double max_sampling_interval_ms = 3'600'000;
  // A requested keep-alive count of 0 is revised to the minimum (§5.13.2.2).
  std::uint32_t min_keep_alive_count = 1;
  std::uint32_t max_keep_alive_count = 10'000;
  std::uint32_t max_lifetime_count = 30'000;
  std::uint32_t max_queue_size = 1000;
  // Queue size of an event item that asks for 0 (§5.12.1.5).
  std::uint32_t default_event_queue_size = 1000;
  // Upper bound of maxNotificationsPerPublish; a request for 0 ("no limit") gets this.
  std::uint32_t max_notifications_per_publish = 10'000;
  std::size_t max_publish_requests_per_session = 20;
  // NotificationMessages kept per subscription for Republish (oldest dropped beyond).
  std::size_t max_retransmission_queue = 100;
};

struct SubscriptionCallbacks {
  // Reads one attribute now (the server implements it over the AddressSpace with the Read
  // service). Used for sampling and to validate items at creation: BadNodeIdUnknown,
  // BadNodeIdInvalid, BadAttributeIdInvalid, BadNotReadable, BadUserAccessDenied,
  // BadIndexRangeInvalid, BadDataEncodingInvalid/Unsupported fail the item's creation; other
  // Bad statuses are reported as the item's value. The engine always asks for
  // TimestampsToReturn::Both (the StatusValueTimestamp trigger needs the source timestamp) and
  // strips what the item did not ask for.
  using Read = std::function<DataValue(const ReadValueId&, TimestampsToReturn)>;
  Read read;
  // EURange of a variable for percent deadband (OPC 10000-8 §5.3.2 AnalogItemType), or
  // nullopt → BadMonitoredItemFilterUnsupported (OPC 10000-4 §7.17.2).
  std::function<std::optional<Range>(const NodeId&)> eu_range;
  // Whether `node` is an event notifier (EventNotifier has SubscribeToEvents) for event items.
  // Unset: only the Server object is.
  std::function<bool(const NodeId&)> is_event_notifier;
  // Whether event type `type` is `base` or a subtype of it (OfType, select clause
  // typeDefinitionId). Unset: only equality.
  std::function<bool(const NodeId& type, const NodeId& base)> is_subtype;
};

// A session is known to the engine by its authentication token.
using SessionKey = NodeId;

class SubscriptionService {
 public:
  using time_point = Clock::time_point;

  SubscriptionService(const Clock& clock, SubscriptionLimits limits, SubscriptionCallbacks callbacks);
  ~SubscriptionService();
  SubscriptionService(const SubscriptionService&) = delete;
  SubscriptionService& operator=(const SubscriptionService&) = delete;

  // The services. Each sets responseHeader (requestHandle, timestamp, serviceResult: e.g.
  // BadNothingToDo, BadTooManyOperations, BadSubscriptionIdInvalid,
  // BadTimestampsToReturnInvalid, BadMonitoringModeInvalid, BadTooManySubscriptions). A
  // subscription belongs to the session that created it: for any other session its id is
  // BadSubscriptionIdInvalid.
  CreateSubscriptionResponse create_subscription(const SessionKey& session,
                                                 const CreateSubscriptionRequest& request);
  ModifySubscriptionResponse modify_subscription(const SessionKey& session,
                                                 const ModifySubscriptionRequest& request);
  SetPublishingModeResponse set_publishing_mode(const SessionKey& session,
                                                const SetPublishingModeRequest& request);
  DeleteSubscriptionsResponse delete_subscriptions(const SessionKey& session,
                                                   const DeleteSubscriptionsRequest& request);
  // `read_as_user` validates the items as the session's user reads them (an item on a node the
  // user may not read fails with BadUserAccessDenied, as Read does); unset: callbacks.read. Items
  // are sampled with callbacks.read: a session's user does not change.
  CreateMonitoredItemsResponse create_monitored_items(const SessionKey& session,
                                                      const CreateMonitoredItemsRequest& request,
                                                      const SubscriptionCallbacks::Read& read_as_user = {});
  ModifyMonitoredItemsResponse modify_monitored_items(const SessionKey& session,
                                                      const ModifyMonitoredItemsRequest& request);
  SetMonitoringModeResponse set_monitoring_mode(const SessionKey& session,
                                                const SetMonitoringModeRequest& request);
  DeleteMonitoredItemsResponse delete_monitored_items(const SessionKey& session,
                                                      const DeleteMonitoredItemsRequest& request);
  RepublishResponse republish(const SessionKey& session, const RepublishRequest& request);

  // Publish is asynchronous (§5.13.5): the request is queued and `respond` is called later
  // (from tick() or from another call on this object, possibly before publish() returns)
  // exactly once, with a PublishResponse or a ServiceFault: BadNoSubscription,
  // BadTooManyPublishRequests (the oldest queued request is the one dropped), BadTimeout when
  // its timeoutHint passes, BadSessionClosed on close_session.
  void publish(const SessionKey& session, const PublishRequest& request,
               std::function<void(Message)> respond);

  // Samples due items, runs every due publishing cycle (§5.13.1.2 state table: keep-alive
  // counter, lifetime counter, late state, publishing disabled, moreNotifications), answers
  // queued Publish requests, times them out, and expires subscriptions whose lifetime counter
  // ran out (StatusChangeNotification BadTimeout for the session's next Publish, then deleted).
  void tick();
  // A server shutting down (OPC 10000-4 §6.6): sends what the subscriptions hold now to the
  // queued Publish requests, whatever their publishing intervals, so clients lose nothing the
  // server had already sampled.
  void flush();
  // When tick() has work next; time_point::max() when nothing is scheduled.
  [[nodiscard]] time_point next_due() const;

  // Events (§5.12.1.4, §7.17.3): an event posted on `notifier` is delivered to the event items
  // on `notifier` and to those on the Server object (i=2253, which gets every event) whose
  // where clause matches. EventFieldList fields follow the select clauses: the field named by
  // the browse path joined with '/' ("Severity", "Prop/Child"); an absent field is a null
  // Variant. "EventType" defaults to event_type.
  struct Event {
    NodeId event_type;
    std::map<std::string, Variant> fields;
  };
  void post_event(const NodeId& notifier, const Event& event);

  // ConditionRefresh (OPC 10000-9 §5.5.7): every event item of the session's subscription `id`
  // gets a RefreshStartEvent, then those of `conditions` its where clause passes, then a
  // RefreshEndEvent (the markers ignore the where clause, §4.5; each has one EventId for all
  // items). BadSubscriptionIdInvalid: not a subscription of the session; BadNothingToDo: it has
  // no event items.
  StatusCode refresh_conditions(const SessionKey& session, std::uint32_t id,
                                const std::vector<Event>& conditions);

  // Session lifecycle: queued Publish requests get BadSessionClosed. With
  // delete_subscriptions=false the subscriptions stay, without a session, until their lifetime
  // expires (TransferSubscriptions could take them; not implemented).
  void close_session(const SessionKey& session, bool delete_subscriptions);

  [[nodiscard]] std::size_t subscription_count() const;
  [[nodiscard]] std::size_t monitored_item_count() const;
  // Publish requests of a session waiting for a response.
  [[nodiscard]] std::size_t queued_publish_count(const SessionKey& session) const;
  [[nodiscard]] const SubscriptionLimits& limits() const;

  struct Impl;

 private:
  std::unique_ptr<Impl> impl_;
};

}  // namespace sf::opcua
