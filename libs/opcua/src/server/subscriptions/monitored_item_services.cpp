// The MonitoredItem service set (OPC 10000-4 §5.12.2 CreateMonitoredItems, §5.12.3
// ModifyMonitoredItems, §5.12.4 SetMonitoringMode, §5.12.6 DeleteMonitoredItems).
#include <utility>

#include "server/subscriptions/engine.hpp"
#include "server/subscriptions/item_config.hpp"
#include "sf/opcua/node_ids.hpp"
#include "sf/opcua/status_codes.hpp"

namespace sf::opcua {

using subs::MonitoredItem;
using subs::Subscription;

namespace {

bool valid_timestamps(TimestampsToReturn t) {
  const auto v = static_cast<std::int32_t>(t);
  return v >= 0 && v <= static_cast<std::int32_t>(TimestampsToReturn::Neither);
}

bool valid_mode(MonitoringMode mode) {
  const auto v = static_cast<std::int32_t>(mode);
  return v >= 0 && v <= static_cast<std::int32_t>(MonitoringMode::Reporting);
}

// The checks every MonitoredItem service starts with; Good or the service result.
StatusCode check_request(SubscriptionService::Impl& m, std::string_view service, std::size_t operations,
                         Subscription* sub, std::uint32_t subscription_id) {
  StatusCode result;
  if (operations == 0) {
    result = status::BadNothingToDo;
  } else if (operations > m.limits.max_operations_per_request) {
    result = status::BadTooManyOperations;
  } else if (sub == nullptr) {
    result = status::BadSubscriptionIdInvalid;
  }
  if (!result.is_good()) {
    m.log->info("{} rejected: {} (subscription {}, {} operations)", service, result.name(), subscription_id,
                operations);
  }
  return result;
}

bool is_event_notifier(const SubscriptionService::Impl& m, const NodeId& node) {
  return m.callbacks.is_event_notifier ? m.callbacks.is_event_notifier(node) : node == NodeId(0, id::Server);
}

}  // namespace

void SubscriptionService::Impl::sample(MonitoredItem& item) {
  if (callbacks.read) {
    subs::offer_sample(item, callbacks.read(item.item, TimestampsToReturn::Both), utc_now());
  }
}

namespace {

MonitoredItemCreateResult create_item(SubscriptionService::Impl& m, Subscription& sub,
                                      const MonitoredItemCreateRequest& request,
                                      TimestampsToReturn timestamps,
                                      const SubscriptionCallbacks::Read& read) {
  MonitoredItemCreateResult r;
  const ReadValueId& target = request.item_to_monitor;
  auto reject = [&](StatusCode code) {
    m.log->debug("CreateMonitoredItems: item {} attribute {} rejected: {}", to_string(target.node_id),
                 target.attribute_id, code.name());
    r.status_code = code;
    return r;
  };
  if (!valid_mode(request.monitoring_mode)) {
    return reject(status::BadMonitoringModeInvalid);
  }
  if (target.attribute_id == 0 || target.attribute_id > subs::kMaxAttributeId) {
    return reject(status::BadAttributeIdInvalid);
  }
  if (sub.items.size() >= m.limits.max_monitored_items_per_subscription ||
      m.item_count >= m.limits.max_monitored_items) {
    return reject(status::BadTooManyMonitoredItems);
  }
  if (!read) {
    return reject(status::BadInternalError);
  }
  const DataValue current = read(target, TimestampsToReturn::Both);
  if (subs::fails_creation(current.status)) {
    return reject(StatusCode(current.status.code()));
  }
  const bool is_event = target.attribute_id == subs::kAttributeEventNotifier;
  if (is_event && !is_event_notifier(m, target.node_id)) {
    return reject(status::BadNotReadable);
  }
  auto config = subs::configure_item(m, sub, target, request.requested_parameters, current.value);
  r.filter_result = std::move(config.filter_result);
  if (!config.status.is_good()) {
    return reject(config.status);
  }
  while (m.next_item_id == 0 || sub.items.contains(m.next_item_id)) {
    ++m.next_item_id;
  }
  MonitoredItem& item = sub.items[m.next_item_id++];
  ++m.item_count;
  item.id = m.next_item_id - 1;
  item.item = target;
  item.mode = request.monitoring_mode;
  item.timestamps = timestamps;
  item.client_handle = request.requested_parameters.client_handle;
  item.sampling_interval_ms = config.sampling_interval_ms;
  item.queue_size = config.queue_size;
  item.discard_oldest = request.requested_parameters.discard_oldest;
  item.is_event = is_event;
  item.data_filter = config.data_filter;
  item.event_filter = std::move(config.event_filter);
  if (!is_event && item.enabled()) {
    // §5.12.1.2: the first sample is reported as the initial value.
    subs::offer_sample(item, current, m.utc_now());
    item.schedule_first_sample(m.clock.now());
  }
  r.monitored_item_id = item.id;
  r.revised_sampling_interval = item.sampling_interval_ms;
  r.revised_queue_size = item.queue_size;
  return r;
}

MonitoredItemModifyResult modify_item(SubscriptionService::Impl& m, Subscription& sub,
                                      const MonitoredItemModifyRequest& request,
                                      TimestampsToReturn timestamps) {
  MonitoredItemModifyResult r;
  const auto it = sub.items.find(request.monitored_item_id);
  if (it == sub.items.end()) {
    m.log->debug("ModifyMonitoredItems: unknown item {}", request.monitored_item_id);
    r.status_code = status::BadMonitoredItemIdInvalid;
    return r;
  }
  MonitoredItem& item = it->second;
  const MonitoringParameters& p = request.requested_parameters;
  const Variant value = item.last ? item.last->value
                                  : (m.callbacks.read && !item.is_event
                                         ? m.callbacks.read(item.item, TimestampsToReturn::Both).value
                                         : Variant{});
  auto config = subs::configure_item(m, sub, item.item, p, value);
  r.filter_result = std::move(config.filter_result);
  if (!config.status.is_good()) {
    m.log->debug("ModifyMonitoredItems: item {} rejected: {}", item.id, config.status.name());
    r.status_code = config.status;
    return r;
  }
  item.client_handle = p.client_handle;
  item.timestamps = timestamps;
  if (config.sampling_interval_ms != item.sampling_interval_ms) {
    item.sampling_interval_ms = config.sampling_interval_ms;
    item.schedule_first_sample(m.clock.now());
  }
  item.discard_oldest = p.discard_oldest;
  subs::resize_queue(item, config.queue_size);
  item.data_filter = config.data_filter;
  if (item.is_event) {
    item.event_filter = std::move(config.event_filter);
  }
  r.revised_sampling_interval = item.sampling_interval_ms;
  r.revised_queue_size = item.queue_size;
  return r;
}

// §5.12.4: Disabled stops sampling and drops the queue; enabling reports a first sample as
// soon as possible; Sampling ↔ Reporting keeps the queue (Reporting then reports it).
void change_mode(SubscriptionService::Impl& m, MonitoredItem& item, MonitoringMode mode) {
  if (mode == item.mode) {
    return;
  }
  const bool was_enabled = item.enabled();
  item.mode = mode;
  if (mode == MonitoringMode::Disabled) {
    item.clear_queue();
  } else if (!was_enabled && !item.is_event) {
    m.sample(item);
    item.schedule_first_sample(m.clock.now());
  }
}

}  // namespace

CreateMonitoredItemsResponse SubscriptionService::create_monitored_items(
    const SessionKey& session, const CreateMonitoredItemsRequest& request,
    const SubscriptionCallbacks::Read& read_as_user) {
  Impl& m = *impl_;
  CreateMonitoredItemsResponse response;
  Subscription* sub = m.find(session, request.subscription_id);
  StatusCode result =
      check_request(m, "CreateMonitoredItems", request.items_to_create.size(), sub, request.subscription_id);
  if (result.is_good() && !valid_timestamps(request.timestamps_to_return)) {
    m.log->info("CreateMonitoredItems rejected: invalid timestampsToReturn");
    result = status::BadTimestampsToReturnInvalid;
  }
  response.response_header = m.header(request.request_header, result);
  if (!result.is_good()) {
    return response;
  }
  sub->reset_lifetime();
  const SubscriptionCallbacks::Read& read = read_as_user ? read_as_user : m.callbacks.read;
  for (const auto& item : request.items_to_create) {
    response.results.push_back(create_item(m, *sub, item, request.timestamps_to_return, read));
  }
  return response;
}

ModifyMonitoredItemsResponse SubscriptionService::modify_monitored_items(
    const SessionKey& session, const ModifyMonitoredItemsRequest& request) {
  Impl& m = *impl_;
  ModifyMonitoredItemsResponse response;
  Subscription* sub = m.find(session, request.subscription_id);
  StatusCode result =
      check_request(m, "ModifyMonitoredItems", request.items_to_modify.size(), sub, request.subscription_id);
  if (result.is_good() && !valid_timestamps(request.timestamps_to_return)) {
    m.log->info("ModifyMonitoredItems rejected: invalid timestampsToReturn");
    result = status::BadTimestampsToReturnInvalid;
  }
  response.response_header = m.header(request.request_header, result);
  if (!result.is_good()) {
    return response;
  }
  sub->reset_lifetime();
  for (const auto& item : request.items_to_modify) {
    response.results.push_back(modify_item(m, *sub, item, request.timestamps_to_return));
  }
  return response;
}

SetMonitoringModeResponse SubscriptionService::set_monitoring_mode(const SessionKey& session,
                                                                   const SetMonitoringModeRequest& request) {
  Impl& m = *impl_;
  SetMonitoringModeResponse response;
  Subscription* sub = m.find(session, request.subscription_id);
  StatusCode result =
      check_request(m, "SetMonitoringMode", request.monitored_item_ids.size(), sub, request.subscription_id);
  if (result.is_good() && !valid_mode(request.monitoring_mode)) {
    m.log->info("SetMonitoringMode rejected: invalid monitoring mode {}",
                static_cast<std::int32_t>(request.monitoring_mode));
    result = status::BadMonitoringModeInvalid;
  }
  response.response_header = m.header(request.request_header, result);
  if (!result.is_good()) {
    return response;
  }
  sub->reset_lifetime();
  for (const std::uint32_t id : request.monitored_item_ids) {
    const auto it = sub->items.find(id);
    if (it == sub->items.end()) {
      m.log->debug("SetMonitoringMode: unknown item {}", id);
      response.results.push_back(status::BadMonitoredItemIdInvalid);
      continue;
    }
    change_mode(m, it->second, request.monitoring_mode);
    response.results.push_back(status::Good);
  }
  return response;
}

DeleteMonitoredItemsResponse SubscriptionService::delete_monitored_items(
    const SessionKey& session, const DeleteMonitoredItemsRequest& request) {
  Impl& m = *impl_;
  DeleteMonitoredItemsResponse response;
  Subscription* sub = m.find(session, request.subscription_id);
  const StatusCode result = check_request(m, "DeleteMonitoredItems", request.monitored_item_ids.size(), sub,
                                          request.subscription_id);
  response.response_header = m.header(request.request_header, result);
  if (!result.is_good()) {
    return response;
  }
  sub->reset_lifetime();
  for (const std::uint32_t id : request.monitored_item_ids) {
    if (sub->items.erase(id) == 0) {
      m.log->debug("DeleteMonitoredItems: unknown item {}", id);
      response.results.push_back(status::BadMonitoredItemIdInvalid);
      continue;
    }
    --m.item_count;
    response.results.push_back(status::Good);
  }
  return response;
}

}  // namespace sf::opcua
