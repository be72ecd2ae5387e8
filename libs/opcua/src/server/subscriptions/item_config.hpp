// The parameters of a monitored item as revised and validated for CreateMonitoredItems and
// ModifyMonitoredItems (OPC 10000-4 §5.12.2, §5.12.3, §7.16 MonitoringParameters). Internal.
#pragma once

#include <memory>

#include "server/subscriptions/engine.hpp"

namespace sf::opcua::subs {

struct ItemConfig {
  StatusCode status;
  double sampling_interval_ms = 0;
  std::uint32_t queue_size = 1;
  DataChangeSettings data_filter;
  std::shared_ptr<const CompiledEventFilter> event_filter;
  ExtensionObject filter_result;  // EventFilterResult when an event filter has errors
};

// The item is an event item when it monitors the EventNotifier attribute; `value` is its
// current value (a deadband needs a numeric one).
ItemConfig configure_item(const SubscriptionService::Impl& engine, const Subscription& sub,
                          const ReadValueId& item, const MonitoringParameters& parameters,
                          const Variant& value);

// Read errors that fail an item's creation instead of being reported as its value.
bool fails_creation(StatusCode read_status);

// Shrinks a queue to a new size, discarding per the item's policy (§5.12.1.5).
void resize_queue(MonitoredItem& item, std::uint32_t size);

}  // namespace sf::opcua::subs
