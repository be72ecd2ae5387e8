// Publish and the publishing cycle (OPC 10000-4 §5.13.1.1-§5.13.1.4, §5.13.5): the sessions'
// Publish queues, keep-alives, the late state, lifetime expiry and the timer that drives them.
#include <algorithm>
#include <utility>

#include "server/subscriptions/engine.hpp"
#include "sf/opcua/status_codes.hpp"

namespace sf::opcua {

using subs::PendingPublish;
using subs::SessionState;
using subs::Subscription;

namespace {

// A timer that stalled longer than this many publishing intervals skips the older cycles.
constexpr std::int64_t kMaxCatchUpCycles = 1000;

}  // namespace

SessionState* SubscriptionService::Impl::session_of(const Subscription& sub) {
  if (!sub.session) {
    return nullptr;
  }
  const auto it = sessions.find(*sub.session);
  return it == sessions.end() ? nullptr : &it->second;
}

void SubscriptionService::Impl::deliver() {
  // A callback may call back into the engine; that call's responses join this loop.
  if (delivering) {
    return;
  }
  delivering = true;
  while (!outbox.empty()) {
    auto batch = std::move(outbox);
    outbox.clear();
    for (auto& [respond, message] : batch) {
      if (respond) {
        respond(std::move(message));
      }
    }
  }
  delivering = false;
}

void SubscriptionService::Impl::fault(PendingPublish request, StatusCode code) {
  ServiceFault f;
  f.response_header.timestamp = utc_now();
  f.response_header.request_handle = request.request_handle;
  f.response_header.service_result = code;
  outbox.emplace_back(std::move(request.respond), Message(std::move(f)));
}

void SubscriptionService::Impl::fail_if_no_subscription(const SessionKey& key) {
  const auto it = sessions.find(key);
  if (it == sessions.end() || !it->second.subscriptions.empty() || !it->second.status_changes.empty()) {
    return;
  }
  auto queue = std::move(it->second.publish_queue);
  it->second.publish_queue.clear();
  for (auto& pending : queue) {
    fault(std::move(pending), status::BadNoSubscription);
  }
}

// Answers the oldest queued Publish request of sub's session with notifications or a
// keep-alive (which carries the next sequence number and no notifications, §7.21).
void SubscriptionService::Impl::send(Subscription& sub, bool notifications) {
  SessionState& state = *session_of(sub);
  PendingPublish request = std::move(state.publish_queue.front());
  state.publish_queue.pop_front();
  PublishResponse r;
  r.response_header.timestamp = utc_now();
  r.response_header.request_handle = request.request_handle;
  r.subscription_id = sub.id;
  r.results = std::move(request.results);
  if (notifications) {
    r.notification_message = sub.collect(utc_now());
    sub.retain(r.notification_message, limits.max_retransmission_queue);
    r.more_notifications = sub.more_notifications;
  } else {
    r.notification_message.sequence_number = sub.next_sequence_number;
    r.notification_message.publish_time = utc_now();
  }
  // "including the sequence number of the NotificationMessage sent in this response"
  r.available_sequence_numbers = sub.available_sequence_numbers();
  sub.late = false;
  sub.message_sent = true;
  sub.empty_cycles = 0;
  sub.reset_lifetime();
  outbox.emplace_back(std::move(request.respond), Message(std::move(r)));
}

// Gives queued Publish requests to what waits for one: final StatusChange messages first, then
// late subscriptions (the longest waiting first), then subscriptions with moreNotifications.
void SubscriptionService::Impl::serve(const SessionKey& key) {
  const auto it = sessions.find(key);
  if (it == sessions.end()) {
    return;
  }
  SessionState& state = it->second;
  while (!state.publish_queue.empty()) {
    if (!state.status_changes.empty()) {
      PendingPublish request = std::move(state.publish_queue.front());
      state.publish_queue.pop_front();
      PublishResponse r;
      r.response_header.timestamp = utc_now();
      r.response_header.request_handle = request.request_handle;
      r.subscription_id = state.status_changes.front().first;
      r.notification_message = std::move(state.status_changes.front().second);
      r.results = std::move(request.results);
      state.status_changes.pop_front();
      outbox.emplace_back(std::move(request.respond), Message(std::move(r)));
      continue;
    }
    Subscription* next = nullptr;
    for (const std::uint32_t id : state.subscriptions) {
      Subscription& s = subscriptions.at(id);
      if (s.late) {
        if (next == nullptr || !next->late || s.late_since < next->late_since) {
          next = &s;
        }
      } else if (next == nullptr && s.more_notifications && s.publishing_enabled && s.has_notifications()) {
        next = &s;
      }
    }
    if (next == nullptr) {
      break;
    }
    send(*next, next->publishing_enabled && next->has_notifications());
  }
  fail_if_no_subscription(key);
}

// The lifetime ran out (§5.13.1.1): the session's next Publish gets a StatusChangeNotification
// with BadTimeout, and the subscription is gone.
void SubscriptionService::Impl::expire(Subscription& sub) {
  log->info("subscription {} expired after {} publishing cycles without a Publish request", sub.id,
            sub.lifetime_count);
  if (SessionState* state = session_of(sub)) {
    NotificationMessage message;
    message.sequence_number = sub.take_sequence_number();
    message.publish_time = utc_now();
    StatusChangeNotification change;
    change.status = status::BadTimeout;
    message.notification_data.push_back(ExtensionObject::make(std::move(change)));
    state->status_changes.emplace_back(sub.id, std::move(message));
  }
  delete_subscription(sub.id);
}

// One publishing cycle (§5.13.1.2 state table, with the keep-alive counter counting up).
void SubscriptionService::Impl::run_cycle(Subscription& sub) {
  SessionState* state = session_of(sub);
  const bool queued = state != nullptr && !state->publish_queue.empty();
  if (!queued) {
    // The lifetime counter counts consecutive cycles without a Publish request (§5.13.1.1).
    if (sub.lifetime_counter <= 1) {
      expire(sub);
      return;
    }
    --sub.lifetime_counter;
  }
  if (sub.late) {
    return;
  }
  const bool available = sub.publishing_enabled && sub.has_notifications();
  bool due = available;
  if (!available) {
    ++sub.empty_cycles;
    // The first cycle sends a keep-alive when there is nothing else (§5.13.1.2 #6).
    due = !sub.message_sent || sub.empty_cycles >= sub.max_keep_alive_count;
  }
  if (!due) {
    return;
  }
  if (queued) {
    send(sub, available);
  } else {
    sub.late = true;
    sub.late_since = sub.next_cycle;
  }
}

void SubscriptionService::Impl::sample_due(Subscription& sub, time_point until, time_point now) {
  for (auto& [id, item] : sub.items) {
    if (item.is_event || !item.enabled() || item.next_sample > until) {
      continue;
    }
    sample(item);
    const auto interval = std::max(subs::milliseconds(item.sampling_interval_ms), Clock::duration(1));
    item.next_sample += interval;
    // Samples missed while the timer was late are not made up: a read now gives the same value.
    if (item.next_sample <= now) {
      item.next_sample += interval * ((now - item.next_sample) / interval + 1);
    }
  }
}

void SubscriptionService::publish(const SessionKey& session, const PublishRequest& request,
                                  std::function<void(Message)> respond) {
  Impl& m = *impl_;
  PendingPublish pending;
  pending.request_handle = request.request_header.request_handle;
  pending.respond = std::move(respond);
  if (request.request_header.timeout_hint > 0) {
    pending.deadline = m.clock.now() + subs::milliseconds(request.request_header.timeout_hint);
  }
  const auto it = m.sessions.find(session);
  if (request.subscription_acknowledgements.size() > m.limits.max_operations_per_request) {
    m.log->info("Publish rejected: {} acknowledgements", request.subscription_acknowledgements.size());
    m.fault(std::move(pending), status::BadTooManyOperations);
    m.deliver();
    return;
  }
  // §5.13.5: acknowledgements first; the response carries one result per acknowledgement.
  for (const auto& ack : request.subscription_acknowledgements) {
    Subscription* sub = m.find(session, ack.subscription_id);
    const StatusCode st =
        sub != nullptr ? sub->acknowledge(ack.sequence_number) : status::BadSubscriptionIdInvalid;
    if (!st.is_good()) {
      m.log->debug("Publish: acknowledgement {}/{}: {}", ack.subscription_id, ack.sequence_number, st.name());
    }
    pending.results.push_back(st);
  }
  if (it == m.sessions.end() || (it->second.subscriptions.empty() && it->second.status_changes.empty())) {
    m.log->debug("Publish rejected: the session has no subscription");
    m.fault(std::move(pending), status::BadNoSubscription);
    m.deliver();
    return;
  }
  SessionState& state = it->second;
  if (state.publish_queue.size() >= m.limits.max_publish_requests_per_session) {
    m.log->info("Publish: too many queued requests ({}), the oldest is dropped", state.publish_queue.size());
    m.fault(std::move(state.publish_queue.front()), status::BadTooManyPublishRequests);
    state.publish_queue.pop_front();
  }
  state.publish_queue.push_back(std::move(pending));
  m.serve(session);
  m.deliver();
}

void SubscriptionService::flush() {
  Impl& m = *impl_;
  for (auto& [id, sub] : m.subscriptions) {
    const subs::SessionState* state = m.session_of(sub);
    while (state != nullptr && !state->publish_queue.empty() && sub.publishing_enabled &&
           sub.has_notifications()) {
      m.send(sub, true);
    }
  }
  m.deliver();
}

void SubscriptionService::tick() {
  Impl& m = *impl_;
  const time_point now = m.clock.now();
  auto time_out = [&m](time_point until) {
    for (auto& [key, state] : m.sessions) {
      auto& q = state.publish_queue;
      for (auto it = q.begin(); it != q.end();) {
        if (it->deadline <= until) {
          m.log->debug("Publish request {} timed out", it->request_handle);
          m.fault(std::move(*it), status::BadTimeout);
          it = q.erase(it);
        } else {
          ++it;
        }
      }
    }
  };
  for (auto& [id, sub] : m.subscriptions) {
    const auto interval = sub.interval();
    if (now - sub.next_cycle > interval * kMaxCatchUpCycles) {
      sub.next_cycle += interval * ((now - sub.next_cycle) / interval - kMaxCatchUpCycles);
    }
  }
  // Cycles run in time order across subscriptions, so they compete for Publish requests as
  // they would have with a punctual timer.
  for (;;) {
    Subscription* due = nullptr;
    for (auto& [id, sub] : m.subscriptions) {
      if (sub.next_cycle <= now && (due == nullptr || sub.next_cycle < due->next_cycle)) {
        due = &sub;
      }
    }
    if (due == nullptr) {
      break;
    }
    const std::uint32_t id = due->id;
    const time_point at = due->next_cycle;
    time_out(at);
    m.sample_due(*due, at, now);
    m.run_cycle(*due);  // may delete the subscription
    if (auto it = m.subscriptions.find(id); it != m.subscriptions.end()) {
      it->second.next_cycle = at + it->second.interval();
    }
  }
  for (auto& [id, sub] : m.subscriptions) {
    m.sample_due(sub, now, now);
  }
  time_out(now);
  m.deliver();
}

SubscriptionService::time_point SubscriptionService::next_due() const {
  time_point due = time_point::max();
  for (const auto& [id, sub] : impl_->subscriptions) {
    due = std::min({due, sub.next_cycle, sub.next_sample_due()});
  }
  for (const auto& [key, state] : impl_->sessions) {
    for (const auto& pending : state.publish_queue) {
      due = std::min(due, pending.deadline);
    }
  }
  return due;
}

}  // namespace sf::opcua
