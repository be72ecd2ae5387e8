// Event delivery to event monitored items (OPC 10000-4 §5.12.1.4 "Events", §7.17.3 EventFilter)
// and the EventQueueOverflowEventType events of overflowing queues (§5.12.1.5,
// OPC 10000-5 §6.4.34).
#include <cstdint>

#include "server/subscriptions/engine.hpp"
#include "sf/opcua/node_ids.hpp"

namespace sf::opcua {
namespace {

// OPC 10000-9 §5.11.2, §5.11.3 (NodeIds.csv).
constexpr std::uint32_t kRefreshStartEventType = 2787;
constexpr std::uint32_t kRefreshEndEventType = 2788;

// A unique EventId for an event the engine makes itself.
ByteString internal_event_id(std::uint64_t number) {
  Bytes id = {'s', 'f', '-', 'o', 'v', 'f', 0, 0};
  for (int shift = 0; shift < 64; shift += 8) {
    id.push_back(static_cast<std::uint8_t>(number >> shift));
  }
  return ByteString(std::move(id));
}

// An event the server makes itself, from its Server object, of severity 1.
subs::Event internal_event(std::uint32_t type, ByteString event_id, const char* source_name,
                           const char* message, DateTime now) {
  subs::Event e;
  e.event_type = NodeId(0, type);
  e.fields["EventId"] = Variant(std::move(event_id));
  e.fields["EventType"] = Variant(e.event_type);
  e.fields["SourceNode"] = Variant(NodeId(0, id::Server));
  e.fields["SourceName"] = Variant(source_name);
  e.fields["Time"] = Variant(now);
  e.fields["ReceiveTime"] = Variant(now);
  e.fields["Message"] = Variant(LocalizedText("", message));
  e.fields["Severity"] = Variant(std::uint16_t{1});
  return e;
}

// "The SourceNode ... shall be assigned to the NodeId of the Server Object. The SourceName ...
// shall be 'Internal/EventQueueOverflow'." (OPC 10000-5 §6.4.34)
subs::Event overflow_event(ByteString event_id, DateTime now) {
  return internal_event(id::EventQueueOverflowEventType, std::move(event_id), "Internal/EventQueueOverflow",
                        "Event queue overflow", now);
}

// The RefreshStartEvent or RefreshEndEvent of a ConditionRefresh (OPC 10000-9 §5.11).
subs::Event refresh_marker(std::uint32_t type, ByteString event_id, DateTime now) {
  return internal_event(type, std::move(event_id), "Internal/ConditionRefresh",
                        type == kRefreshStartEventType ? "Refresh start" : "Refresh end", now);
}

}  // namespace

StatusCode SubscriptionService::refresh_conditions(const SessionKey& session, std::uint32_t id,
                                                   const std::vector<Event>& conditions) {
  Impl& m = *impl_;
  subs::Subscription* sub = m.find(session, id);
  if (sub == nullptr) {
    return status::BadSubscriptionIdInvalid;
  }
  const DateTime now = m.utc_now();
  const subs::Event start =
      refresh_marker(kRefreshStartEventType, internal_event_id(++m.internal_events), now);
  const subs::Event end = refresh_marker(kRefreshEndEventType, internal_event_id(++m.internal_events), now);
  bool any = false;
  for (auto& [item_id, item] : sub->items) {
    if (!item.is_event || !item.enabled()) {
      continue;
    }
    any = true;
    const subs::CompiledEventFilter& filter = *item.event_filter;
    auto make_overflow = [&m, &filter, now] {
      return subs::select_fields(filter, overflow_event(internal_event_id(++m.internal_events), now),
                                 m.types);
    };
    subs::enqueue_event(item, subs::select_fields(filter, start, m.types), make_overflow);
    for (const Event& condition : conditions) {
      if (subs::where_matches(filter.filter.where_clause, condition, m.types)) {
        subs::enqueue_event(item, subs::select_fields(filter, condition, m.types), make_overflow);
      }
    }
    subs::enqueue_event(item, subs::select_fields(filter, end, m.types), make_overflow);
  }
  return any ? status::Good : status::BadNothingToDo;
}

void SubscriptionService::post_event(const NodeId& notifier, const Event& event) {
  Impl& m = *impl_;
  const NodeId server(0, id::Server);
  const DateTime now = m.utc_now();
  std::size_t delivered = 0;
  for (auto& [sub_id, sub] : m.subscriptions) {
    for (auto& [item_id, item] : sub.items) {
      if (!item.is_event || !item.enabled() ||
          (item.item.node_id != notifier && item.item.node_id != server)) {
        continue;
      }
      const subs::CompiledEventFilter& filter = *item.event_filter;
      if (!subs::where_matches(filter.filter.where_clause, event, m.types)) {
        continue;
      }
      // The overflow event bypasses the where clause.
      auto make_overflow = [&m, &filter, now] {
        return subs::select_fields(filter, overflow_event(internal_event_id(++m.internal_events), now),
                                   m.types);
      };
      subs::enqueue_event(item, subs::select_fields(filter, event, m.types), make_overflow);
      ++delivered;
    }
  }
  m.log->trace("event of type {} on {} delivered to {} items", to_string(event.event_type),
               to_string(notifier), delivered);
}

}  // namespace sf::opcua
