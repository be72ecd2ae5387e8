// Event delivery to event monitored items (OPC 10000-4 §5.12.1.4 "Events", §7.17.3 EventFilter)
// and the EventQueueOverflowEventType events of overflowing queues (§5.12.1.5,
// OPC 10000-5 §6.4.34).
#include <cstdint>

#include "server/subscriptions/engine.hpp"
#include "sf/opcua/node_ids.hpp"

namespace sf::opcua {
namespace {

// A unique EventId for an event the engine makes itself.
ByteString internal_event_id(std::uint64_t number) {
  Bytes id = {'s', 'f', '-', 'o', 'v', 'f', 0, 0};
  for (int shift = 0; shift < 64; shift += 8) {
    id.push_back(static_cast<std::uint8_t>(number >> shift));
  }
  return ByteString(std::move(id));
}

subs::Event overflow_event(ByteString event_id, DateTime now) {
  subs::Event e;
  e.event_type = NodeId(0, id::EventQueueOverflowEventType);
  e.fields["EventId"] = Variant(std::move(event_id));
  e.fields["EventType"] = Variant(e.event_type);
  // "The SourceNode ... shall be assigned to the NodeId of the Server Object. The SourceName
  // ... shall be 'Internal/EventQueueOverflow'."
  e.fields["SourceNode"] = Variant(NodeId(0, id::Server));
  e.fields["SourceName"] = Variant("Internal/EventQueueOverflow");
  e.fields["Time"] = Variant(now);
  e.fields["ReceiveTime"] = Variant(now);
  e.fields["Message"] = Variant(LocalizedText("", "Event queue overflow"));
  e.fields["Severity"] = Variant(std::uint16_t{1});
  return e;
}

}  // namespace

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
