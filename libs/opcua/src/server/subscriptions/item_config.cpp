// Revision and validation of MonitoringParameters (OPC 10000-4 §7.16) and of the item's filter
// (§7.17): DataChangeFilter for Value attributes, EventFilter for EventNotifier attributes.
#include "server/subscriptions/item_config.hpp"

#include <algorithm>
#include <cmath>
#include <optional>

#include "sf/opcua/status_codes.hpp"

namespace sf::opcua::subs {
namespace {

// §7.16: -1 (any negative) = the publishing interval, 0 = the fastest practical rate; the
// revised interval is never below the requested one unless over the maximum.
double revise_sampling(const SubscriptionLimits& limits, double requested, double publishing_interval) {
  double s = std::isnan(requested) || requested < 0 ? publishing_interval : requested;
  s = std::max(s, limits.min_sampling_interval_ms);
  return std::min(s, limits.max_sampling_interval_ms);
}

void configure_event(const SubscriptionService::Impl& engine, const ExtensionObject& filter,
                     ItemConfig& out) {
  const auto* event_filter = filter.get_if<EventFilter>();
  if (event_filter == nullptr) {
    // An event item needs an EventFilter (§7.17.3).
    out.status = filter.empty()                                 ? status::BadMonitoredItemFilterInvalid
                 : filter.get_if<DataChangeFilter>() != nullptr ? status::BadFilterNotAllowed
                                                                : status::BadMonitoredItemFilterUnsupported;
    return;
  }
  auto check = check_event_filter(*event_filter, engine.types);
  if (check.has_errors) {
    out.filter_result = ExtensionObject::make(std::move(check.result));
  }
  out.status = check.status;
  out.event_filter = std::make_shared<const CompiledEventFilter>(std::move(check.compiled));
}

void configure_data(const SubscriptionService::Impl& engine, const ReadValueId& item,
                    const ExtensionObject& filter, const Variant& value, ItemConfig& out) {
  if (filter.empty()) {
    return;
  }
  const auto* data_filter = filter.get_if<DataChangeFilter>();
  if (data_filter == nullptr) {
    out.status = filter.get_if<EventFilter>() != nullptr ? status::BadFilterNotAllowed
                                                         : status::BadMonitoredItemFilterUnsupported;
    return;
  }
  // §7.17.2: the DataChangeFilter is for the Value attribute only.
  if (item.attribute_id != kAttributeValue) {
    out.status = status::BadFilterNotAllowed;
    return;
  }
  std::optional<Range> range;
  if (data_filter->deadband_type == static_cast<std::uint32_t>(DeadbandType::Percent) &&
      engine.callbacks.eu_range) {
    range = engine.callbacks.eu_range(item.node_id);
  }
  const auto check = check_data_change_filter(*data_filter, value, range);
  out.status = check.status;
  out.data_filter = check.settings;
}

}  // namespace

ItemConfig configure_item(const SubscriptionService::Impl& engine, const Subscription& sub,
                          const ReadValueId& item, const MonitoringParameters& parameters,
                          const Variant& value) {
  ItemConfig out;
  const SubscriptionLimits& limits = engine.limits;
  if (item.attribute_id == kAttributeEventNotifier) {
    configure_event(engine, parameters.filter, out);
    // Events are not sampled: they are queued as they occur.
    out.sampling_interval_ms = 0;
    out.queue_size = parameters.queue_size == 0 ? limits.default_event_queue_size : parameters.queue_size;
  } else {
    configure_data(engine, item, parameters.filter, value, out);
    out.sampling_interval_ms =
        revise_sampling(limits, parameters.sampling_interval, sub.publishing_interval_ms);
    out.queue_size = std::max<std::uint32_t>(parameters.queue_size, 1);
  }
  out.queue_size = std::min(out.queue_size, std::max<std::uint32_t>(limits.max_queue_size, 1));
  return out;
}

bool fails_creation(StatusCode read_status) {
  switch (read_status.code()) {
    case status::BadNodeIdUnknown.value():
    case status::BadNodeIdInvalid.value():
    case status::BadAttributeIdInvalid.value():
    case status::BadNotReadable.value():
    case status::BadUserAccessDenied.value():
    case status::BadIndexRangeInvalid.value():
    case status::BadDataEncodingInvalid.value():
    case status::BadDataEncodingUnsupported.value():
      return true;
    default:
      return false;
  }
}

void resize_queue(MonitoredItem& item, std::uint32_t size) {
  item.queue_size = size;
  bool discarded = false;
  while (item.values.size() > size) {
    discarded = true;
    if (item.discard_oldest) {
      item.values.pop_front();
    } else {
      item.values.pop_back();
    }
  }
  if (discarded && size > 1) {
    DataValue& marked = item.discard_oldest ? item.values.front() : item.values.back();
    marked.status = StatusCode(marked.status.value() | kOverflowInfoBits);
  }
  while (item.events.size() > size) {
    if (item.discard_oldest) {
      item.events.pop_front();
    } else {
      item.events.pop_back();
    }
  }
}

}  // namespace sf::opcua::subs
