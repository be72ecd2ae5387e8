// A subscription's parameters, notifications and retransmission queue (OPC 10000-4 §5.13.1).
#include <algorithm>
#include <cstdint>
#include <limits>

#include "server/subscriptions/engine.hpp"

namespace sf::opcua::subs {

RevisedSubscription revise_subscription(const SubscriptionLimits& limits, double interval_ms,
                                        std::uint32_t lifetime_count, std::uint32_t keep_alive_count,
                                        std::uint32_t max_notifications) {
  RevisedSubscription r;
  // §5.13.2.2: 0, negative or NaN get the fastest supported interval.
  r.publishing_interval_ms =
      interval_ms >= limits.min_publishing_interval_ms ? interval_ms : limits.min_publishing_interval_ms;
  r.publishing_interval_ms = std::min(r.publishing_interval_ms, limits.max_publishing_interval_ms);
  // "If the requested value is 0, the Server shall revise with the smallest supported
  // keep-alive count."
  r.max_keep_alive_count = std::clamp(keep_alive_count == 0 ? limits.min_keep_alive_count : keep_alive_count,
                                      limits.min_keep_alive_count, limits.max_keep_alive_count);
  // "The lifetime count shall be a minimum of three times the keep keep-alive count."
  const std::uint64_t min_lifetime = 3ULL * r.max_keep_alive_count;
  const std::uint64_t lifetime = std::max<std::uint64_t>(lifetime_count, min_lifetime);
  r.lifetime_count = static_cast<std::uint32_t>(std::min<std::uint64_t>(lifetime, limits.max_lifetime_count));
  if (r.lifetime_count < min_lifetime) {
    r.max_keep_alive_count = std::max<std::uint32_t>(1, r.lifetime_count / 3);
    r.lifetime_count = std::max(r.lifetime_count, 3 * r.max_keep_alive_count);
  }
  // 0 means "no limit": the server's own limit applies.
  r.max_notifications = max_notifications == 0 || max_notifications > limits.max_notifications_per_publish
                            ? limits.max_notifications_per_publish
                            : max_notifications;
  return r;
}

bool Subscription::has_notifications() const {
  return std::any_of(items.begin(), items.end(),
                     [](const auto& entry) { return entry.second.reporting() && entry.second.queued() > 0; });
}

time_point Subscription::next_sample_due() const {
  time_point due = time_point::max();
  for (const auto& [item_id, item] : items) {
    if (!item.is_event && item.enabled()) {
      due = std::min(due, item.next_sample);
    }
  }
  return due;
}

std::uint32_t Subscription::take_sequence_number() {
  const std::uint32_t n = next_sequence_number;
  next_sequence_number = n == std::numeric_limits<std::uint32_t>::max() ? 1 : n + 1;
  return n;
}

NotificationMessage Subscription::collect(DateTime now) {
  NotificationMessage message;
  message.publish_time = now;
  DataChangeNotification data;
  EventNotificationList events;
  std::size_t budget = max_notifications == 0 ? std::numeric_limits<std::size_t>::max() : max_notifications;
  // Start where the last limited message stopped so that no item starves (moreNotifications).
  auto start = items.lower_bound(resume_from);
  resume_from = 0;
  for (std::size_t n = 0; n < items.size() && budget > 0; ++n, ++start) {
    if (start == items.end()) {
      start = items.begin();
    }
    MonitoredItem& item = start->second;
    if (!item.reporting()) {
      continue;
    }
    for (; budget > 0 && !item.values.empty(); --budget) {
      data.monitored_items.push_back({item.client_handle, std::move(item.values.front())});
      item.values.pop_front();
    }
    for (; budget > 0 && !item.events.empty(); --budget) {
      events.events.push_back({item.client_handle, std::move(item.events.front().fields)});
      item.events.pop_front();
    }
    if (budget == 0) {
      resume_from = item.queued() > 0 ? item.id : item.id + 1;
    }
  }
  more_notifications = has_notifications();
  if (!data.monitored_items.empty()) {
    message.notification_data.push_back(ExtensionObject::make(std::move(data)));
  }
  if (!events.events.empty()) {
    message.notification_data.push_back(ExtensionObject::make(std::move(events)));
  }
  message.sequence_number = take_sequence_number();
  return message;
}

void Subscription::retain(const NotificationMessage& message, std::size_t max) {
  if (max == 0) {
    return;
  }
  while (retransmission.size() >= max) {
    retransmission.pop_front();
  }
  retransmission.push_back(message);
}

Array<std::uint32_t> Subscription::available_sequence_numbers() const {
  Array<std::uint32_t> numbers;
  for (const auto& m : retransmission) {
    numbers.push_back(m.sequence_number);
  }
  return numbers;
}

StatusCode Subscription::acknowledge(std::uint32_t sequence_number) {
  const auto it =
      std::find_if(retransmission.begin(), retransmission.end(),
                   [&](const NotificationMessage& m) { return m.sequence_number == sequence_number; });
  if (it == retransmission.end()) {
    return status::BadSequenceNumberUnknown;
  }
  retransmission.erase(it);
  return status::Good;
}

}  // namespace sf::opcua::subs
