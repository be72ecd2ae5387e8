// The Publish loop (OPC 10000-4 §5.13.5): a few Publish requests stay outstanding so the server
// can answer whenever a subscription has something; each carries the acknowledgements of what
// arrived. NotificationMessages are delivered per subscription in sequence-number order
// (§5.13.1.1): a gap is filled with Republish (§5.13.6) when the server still lists the message
// as available, and given up otherwise; duplicates (a republished message that arrived anyway)
// are dropped.
#include <algorithm>

#include "client_impl.hpp"

namespace sf::opcua {

using client_detail::next_sequence;

namespace {

// Gaps wider than this are not republished message by message.
constexpr std::uint32_t kMaxGap = 1000;

std::uint32_t previous_sequence(std::uint32_t n) {
  return n <= 1 ? UINT32_MAX : n - 1U;
}

}  // namespace

Client::Impl::Subscription* Client::Impl::find_by_server_id(std::uint32_t server_id) {
  for (auto& [id, sub] : subscriptions) {
    if (sub.server_id == server_id && server_id != 0) {
      return &sub;
    }
  }
  return nullptr;
}

bool Client::Impl::has_server_subscription() const {
  return std::any_of(subscriptions.begin(), subscriptions.end(),
                     [](const auto& entry) { return entry.second.server_id != 0; });
}

std::chrono::milliseconds Client::Impl::publish_timeout() const {
  // The server may hold a request for a whole keep-alive period of the slowest subscription,
  // once for each outstanding request.
  double cycle_ms = 0;
  for (const auto& [id, sub] : subscriptions) {
    cycle_ms = std::max(cycle_ms, sub.revised_interval_ms * static_cast<double>(sub.revised_keep_alive));
  }
  return config.request_timeout +
         std::chrono::milliseconds(static_cast<std::int64_t>(cycle_ms * static_cast<double>(publish_target)));
}

void Client::Impl::pump_publish() {
  if (shut_down || !channel || !session || !session->activated || publish_retry_timer != 0) {
    return;
  }
  if (!has_server_subscription()) {
    return;
  }
  while (publish_outstanding < publish_target) {
    send_publish();
  }
}

void Client::Impl::send_publish() {
  PublishRequest request;
  request.subscription_acknowledgements = std::move(pending_acks);
  pending_acks.clear();
  std::vector<SubscriptionAcknowledgement> acks(request.subscription_acknowledgements.begin(),
                                                request.subscription_acknowledgements.end());
  ++publish_outstanding;
  const std::uint64_t generation = channel_generation;
  const std::uint64_t epoch = session_epoch;
  send(std::move(request), publish_timeout(),
       [this, generation, epoch, acks = std::move(acks)](Result<PublishResponse> response) {
         // Acknowledgements that may not have arrived go out again with the next request (a
         // duplicate only earns a BadSequenceNumberUnknown).
         if (!response && epoch == session_epoch &&
             client_detail::is_transport_error(status_of(response.error()))) {
           pending_acks.insert(pending_acks.end(), acks.begin(), acks.end());
         }
         if (generation != channel_generation) {
           return;  // a request of a dropped channel; the counter was reset with it
         }
         --publish_outstanding;
         if (epoch != session_epoch) {
           pump_publish();
           return;
         }
         on_publish(std::move(response));
         pump_publish();
       });
}

void Client::Impl::on_publish(Result<PublishResponse> response) {
  if (!response) {
    const StatusCode code = status_of(response.error());
    if (code.code() == status::BadTooManyPublishRequests.code()) {
      // §5.13.5: the server's limit; keep one request fewer outstanding.
      publish_target = std::max<std::size_t>(1, publish_outstanding);
      logger->info("opcua client: server limits outstanding Publish requests to {}", publish_target);
      return;
    }
    if (code.code() == status::BadTimeout.code() || client_detail::is_session_error(code) ||
        client_detail::is_transport_error(code)) {
      return;  // resent at once / handled by session recovery / by the reconnect
    }
    if (code.code() == status::BadNoSubscription.code() && !has_server_subscription()) {
      return;  // the last subscription was deleted; Publish starts again with the next one
    }
    // Anything unexpected: wait a little instead of spinning.
    logger->warn("opcua client {}: Publish failed: {}", config.endpoint_url, response.error().message);
    if (publish_retry_timer == 0) {
      publish_retry_timer = loop.add_timer(std::max(config.reconnect_min, std::chrono::milliseconds(100)),
                                           [weak = weak_from_this()]() {
                                             if (auto self = weak.lock(); self && !self->shut_down) {
                                               self->publish_retry_timer = 0;
                                               self->pump_publish();
                                             }
                                           });
    }
    return;
  }
  Subscription* sub = find_by_server_id(response->subscription_id);
  if (sub == nullptr) {
    logger->debug("opcua client: Publish response for unknown subscription {}", response->subscription_id);
    return;
  }
  const NotificationMessage& message = response->notification_message;
  const std::uint32_t expected = next_sequence(sub->last_delivered);
  if (message.notification_data.empty()) {
    // A keep-alive carries the sequence number the next message will have (§5.13.1.1): anything
    // between what we have and that number was sent and lost.
    if (client_detail::sequence_before(expected, message.sequence_number)) {
      fill_gap(*sub, expected, message.sequence_number, response->available_sequence_numbers);
    }
  } else {
    pending_acks.push_back(SubscriptionAcknowledgement{response->subscription_id, message.sequence_number});
    on_notification(*sub, message, response->available_sequence_numbers);
  }
  if (shut_down) {
    return;
  }
  if (Subscription* still = find_by_server_id(response->subscription_id)) {
    still->last_available = std::move(response->available_sequence_numbers);
  }
}

void Client::Impl::on_notification(Subscription& sub, const NotificationMessage& message,
                                   const Array<std::uint32_t>& available) {
  const std::uint32_t sequence = message.sequence_number;
  const std::uint32_t expected = next_sequence(sub.last_delivered);
  if (client_detail::sequence_before(sequence, expected) || sub.ahead.count(sequence) != 0) {
    logger->debug("opcua client: subscription {}: duplicate notification {} dropped", sub.id, sequence);
    return;
  }
  if (sequence == expected) {
    sub.last_delivered = sequence;
    sub.lost.erase(sequence);
    deliver(sub, message);
    if (!shut_down) {
      flush(sub);
    }
    return;
  }
  sub.ahead.emplace(sequence, message);
  fill_gap(sub, expected, sequence, available);
}

void Client::Impl::fill_gap(Subscription& sub, std::uint32_t from, std::uint32_t to,
                            const Array<std::uint32_t>& available) {
  if (to - from > kMaxGap) {
    logger->warn("opcua client: subscription {}: {} notifications missing; skipping to {}", sub.id, to - from,
                 to);
    sub.last_delivered = previous_sequence(to);
    std::erase_if(sub.ahead,
                  [&](const auto& entry) { return client_detail::sequence_before(entry.first, to); });
    sub.lost.clear();
    flush(sub);
    return;
  }
  for (std::uint32_t n = from; n != to; n = next_sequence(n)) {
    if (sub.ahead.count(n) != 0 || sub.republishing.count(n) != 0 || sub.lost.count(n) != 0) {
      continue;
    }
    if (std::find(available.begin(), available.end(), n) != available.end()) {
      republish(sub, n);
    } else {
      logger->warn("opcua client: subscription {}: notification {} lost (no longer available on the server)",
                   sub.id, n);
      sub.lost.insert(n);
    }
  }
  flush(sub);
}

void Client::Impl::republish(Subscription& sub, std::uint32_t sequence_number) {
  sub.republishing.insert(sequence_number);
  RepublishRequest request;
  request.subscription_id = sub.server_id;
  request.retransmit_sequence_number = sequence_number;
  const SubscriptionId id = sub.id;
  const std::uint32_t server_id = sub.server_id;
  const std::uint64_t epoch = session_epoch;
  logger->debug("opcua client: subscription {}: Republish {}", id, sequence_number);
  send(std::move(request), [this, id, server_id, epoch, sequence_number](Result<RepublishResponse> response) {
    auto entry = subscriptions.find(id);
    if (epoch != session_epoch || entry == subscriptions.end() || entry->second.server_id != server_id) {
      return;
    }
    Subscription& target = entry->second;
    target.republishing.erase(sequence_number);
    if (!response) {
      if (client_detail::is_transport_error(status_of(response.error()))) {
        return;  // asked again after the reconnect or at the next gap
      }
      logger->warn("opcua client: subscription {}: Republish {} failed ({}); notification lost", id,
                   sequence_number, response.error().message);
      target.lost.insert(sequence_number);
    } else {
      // §5.13.6: a retransmitted message stays queued on the server until acknowledged.
      pending_acks.push_back(SubscriptionAcknowledgement{server_id, sequence_number});
      if (!client_detail::sequence_before(sequence_number, next_sequence(target.last_delivered))) {
        target.ahead.emplace(sequence_number, std::move(response->notification_message));
      }
    }
    flush(target);
  });
}

void Client::Impl::flush(Subscription& sub) {
  while (!shut_down) {
    const std::uint32_t next = next_sequence(sub.last_delivered);
    if (auto it = sub.ahead.find(next); it != sub.ahead.end()) {
      NotificationMessage message = std::move(it->second);
      sub.ahead.erase(it);
      sub.last_delivered = next;
      deliver(sub, message);
      continue;
    }
    if (sub.lost.erase(next) != 0) {
      sub.last_delivered = next;
      continue;
    }
    break;
  }
}

void Client::Impl::deliver(Subscription& sub, const NotificationMessage& message) {
  // Callbacks cannot change the subscriptions (public methods post), but one may destroy the
  // Client: stop as soon as it is shut down.
  for (const auto& data : message.notification_data) {
    if (shut_down) {
      return;
    }
    if (const auto* changes = data.get_if<DataChangeNotification>()) {
      for (const auto& change : changes->monitored_items) {
        auto item = sub.items.find(change.client_handle);
        if (item == sub.items.end() || !item->second.on_change) {
          logger->debug("opcua client: data change for unknown client handle {}", change.client_handle);
          continue;
        }
        item->second.on_change(change.value);
        if (shut_down) {
          return;
        }
      }
    } else if (const auto* events = data.get_if<EventNotificationList>()) {
      for (const auto& event : events->events) {
        auto item = sub.items.find(event.client_handle);
        if (item == sub.items.end() || !item->second.on_event) {
          logger->debug("opcua client: event for unknown client handle {}", event.client_handle);
          continue;
        }
        item->second.on_event(std::vector<Variant>(event.event_fields.begin(), event.event_fields.end()));
        if (shut_down) {
          return;
        }
      }
    } else if (const auto* change = data.get_if<StatusChangeNotification>()) {
      logger->warn("opcua client: subscription {}: status change {}", sub.id, to_string(change->status));
      if (change->status.is_bad()) {
        // §5.13.1.1: the server ended the subscription (e.g. BadTimeout, its lifetime ran out):
        // create it again in this session.
        post([this, id = sub.id]() {
          if (!check_connected("re-create subscription")) {
            recreate_subscription(id, [this]() { pump_publish(); });
          }
        });
      }
    } else {
      logger->warn("opcua client: subscription {}: unknown notification data {} rejected", sub.id,
                   to_string(data.type_id()));
    }
  }
}

void Client::Impl::republish_missing() {
  for (auto& [id, sub] : subscriptions) {
    if (sub.server_id == 0) {
      continue;
    }
    const std::uint32_t expected = next_sequence(sub.last_delivered);
    for (const std::uint32_t n : sub.last_available) {
      if (!client_detail::sequence_before(n, expected) && sub.ahead.count(n) == 0 &&
          sub.republishing.count(n) == 0) {
        republish(sub, n);
      }
    }
  }
}

}  // namespace sf::opcua
