// The Subscription service set without Publish (OPC 10000-4 §5.13.2 CreateSubscription,
// §5.13.3 ModifySubscription, §5.13.4 SetPublishingMode, §5.13.6 Republish, §5.13.8
// DeleteSubscriptions) and the engine's bookkeeping.
#include <utility>

#include "server/subscriptions/engine.hpp"
#include "sf/opcua/status_codes.hpp"

namespace sf::opcua {

using subs::Subscription;

SubscriptionService::Impl::Impl(const Clock& c, SubscriptionLimits l, SubscriptionCallbacks cb)
    : clock(c), limits(l), callbacks(std::move(cb)), log(log::get("opcua")), types(callbacks.is_subtype) {}

DateTime SubscriptionService::Impl::utc_now() const {
  return DateTime::from_system_clock(clock.utc_now());
}

ResponseHeader SubscriptionService::Impl::header(const RequestHeader& request, StatusCode result) const {
  ResponseHeader h;
  h.timestamp = utc_now();
  h.request_handle = request.request_handle;
  h.service_result = result;
  return h;
}

Subscription* SubscriptionService::Impl::find(const SessionKey& session, std::uint32_t id) {
  const auto it = subscriptions.find(id);
  if (it == subscriptions.end() || it->second.session != session) {
    return nullptr;
  }
  return &it->second;
}

void SubscriptionService::Impl::delete_subscription(std::uint32_t id) {
  const auto it = subscriptions.find(id);
  if (it == subscriptions.end()) {
    return;
  }
  item_count -= it->second.items.size();
  if (auto* session = session_of(it->second)) {
    session->subscriptions.erase(id);
  }
  subscriptions.erase(it);
}

SubscriptionService::SubscriptionService(const Clock& clock, SubscriptionLimits limits,
                                         SubscriptionCallbacks callbacks)
    : impl_(std::make_unique<Impl>(clock, limits, std::move(callbacks))) {}

SubscriptionService::~SubscriptionService() = default;

CreateSubscriptionResponse SubscriptionService::create_subscription(
    const SessionKey& session, const CreateSubscriptionRequest& request) {
  Impl& m = *impl_;
  CreateSubscriptionResponse response;
  auto& state = m.sessions[session];
  if (state.subscriptions.size() >= m.limits.max_subscriptions_per_session ||
      m.subscriptions.size() >= m.limits.max_subscriptions) {
    m.log->info("CreateSubscription rejected: too many subscriptions ({} in session, {} in all)",
                state.subscriptions.size(), m.subscriptions.size());
    response.response_header = m.header(request.request_header, status::BadTooManySubscriptions);
    return response;
  }
  const auto revised = subs::revise_subscription(
      m.limits, request.requested_publishing_interval, request.requested_lifetime_count,
      request.requested_max_keep_alive_count, request.max_notifications_per_publish);
  while (m.next_subscription_id == 0 || m.subscriptions.contains(m.next_subscription_id)) {
    ++m.next_subscription_id;
  }
  const std::uint32_t id = m.next_subscription_id++;
  Subscription& sub = m.subscriptions[id];
  sub.id = id;
  sub.session = session;
  sub.publishing_interval_ms = revised.publishing_interval_ms;
  sub.max_keep_alive_count = revised.max_keep_alive_count;
  sub.lifetime_count = revised.lifetime_count;
  sub.max_notifications = revised.max_notifications;
  sub.publishing_enabled = request.publishing_enabled;
  sub.priority = request.priority;
  sub.reset_lifetime();
  sub.next_cycle = m.clock.now() + sub.interval();
  state.subscriptions.insert(id);

  response.response_header = m.header(request.request_header);
  response.subscription_id = id;
  response.revised_publishing_interval = revised.publishing_interval_ms;
  response.revised_lifetime_count = revised.lifetime_count;
  response.revised_max_keep_alive_count = revised.max_keep_alive_count;
  return response;
}

ModifySubscriptionResponse SubscriptionService::modify_subscription(
    const SessionKey& session, const ModifySubscriptionRequest& request) {
  Impl& m = *impl_;
  ModifySubscriptionResponse response;
  Subscription* sub = m.find(session, request.subscription_id);
  if (sub == nullptr) {
    m.log->info("ModifySubscription rejected: unknown subscription {}", request.subscription_id);
    response.response_header = m.header(request.request_header, status::BadSubscriptionIdInvalid);
    return response;
  }
  const auto revised = subs::revise_subscription(
      m.limits, request.requested_publishing_interval, request.requested_lifetime_count,
      request.requested_max_keep_alive_count, request.max_notifications_per_publish);
  if (revised.publishing_interval_ms != sub->publishing_interval_ms) {
    sub->publishing_interval_ms = revised.publishing_interval_ms;
    sub->next_cycle = m.clock.now() + sub->interval();
  }
  sub->max_keep_alive_count = revised.max_keep_alive_count;
  sub->lifetime_count = revised.lifetime_count;
  sub->max_notifications = revised.max_notifications;
  sub->priority = request.priority;
  sub->reset_lifetime();

  response.response_header = m.header(request.request_header);
  response.revised_publishing_interval = revised.publishing_interval_ms;
  response.revised_lifetime_count = revised.lifetime_count;
  response.revised_max_keep_alive_count = revised.max_keep_alive_count;
  return response;
}

SetPublishingModeResponse SubscriptionService::set_publishing_mode(const SessionKey& session,
                                                                   const SetPublishingModeRequest& request) {
  Impl& m = *impl_;
  SetPublishingModeResponse response;
  const std::size_t n = request.subscription_ids.size();
  if (n == 0 || n > m.limits.max_operations_per_request) {
    m.log->info("SetPublishingMode rejected: {} subscription ids", n);
    response.response_header =
        m.header(request.request_header, n == 0 ? status::BadNothingToDo : status::BadTooManyOperations);
    return response;
  }
  for (const std::uint32_t id : request.subscription_ids) {
    Subscription* sub = m.find(session, id);
    if (sub == nullptr) {
      m.log->debug("SetPublishingMode: unknown subscription {}", id);
      response.results.push_back(status::BadSubscriptionIdInvalid);
      continue;
    }
    sub->publishing_enabled = request.publishing_enabled;
    sub->reset_lifetime();
    response.results.push_back(status::Good);
  }
  response.response_header = m.header(request.request_header);
  return response;
}

DeleteSubscriptionsResponse SubscriptionService::delete_subscriptions(
    const SessionKey& session, const DeleteSubscriptionsRequest& request) {
  Impl& m = *impl_;
  DeleteSubscriptionsResponse response;
  const std::size_t n = request.subscription_ids.size();
  if (n == 0 || n > m.limits.max_operations_per_request) {
    m.log->info("DeleteSubscriptions rejected: {} subscription ids", n);
    response.response_header =
        m.header(request.request_header, n == 0 ? status::BadNothingToDo : status::BadTooManyOperations);
    return response;
  }
  for (const std::uint32_t id : request.subscription_ids) {
    if (m.find(session, id) == nullptr) {
      m.log->debug("DeleteSubscriptions: unknown subscription {}", id);
      response.results.push_back(status::BadSubscriptionIdInvalid);
      continue;
    }
    m.delete_subscription(id);
    response.results.push_back(status::Good);
  }
  response.response_header = m.header(request.request_header);
  // §5.13.8.1: once the last subscription is gone, queued Publish requests get
  // BadNoSubscription.
  m.fail_if_no_subscription(session);
  m.deliver();
  return response;
}

RepublishResponse SubscriptionService::republish(const SessionKey& session, const RepublishRequest& request) {
  Impl& m = *impl_;
  RepublishResponse response;
  Subscription* sub = m.find(session, request.subscription_id);
  if (sub == nullptr) {
    m.log->info("Republish rejected: unknown subscription {}", request.subscription_id);
    response.response_header = m.header(request.request_header, status::BadSubscriptionIdInvalid);
    return response;
  }
  sub->reset_lifetime();
  for (const auto& message : sub->retransmission) {
    if (message.sequence_number == request.retransmit_sequence_number) {
      response.response_header = m.header(request.request_header);
      response.notification_message = message;
      return response;
    }
  }
  m.log->info("Republish: message {} of subscription {} is not available", request.retransmit_sequence_number,
              request.subscription_id);
  response.response_header = m.header(request.request_header, status::BadMessageNotAvailable);
  return response;
}

void SubscriptionService::close_session(const SessionKey& session, bool delete_subscriptions) {
  Impl& m = *impl_;
  const auto it = m.sessions.find(session);
  if (it == m.sessions.end()) {
    return;
  }
  auto state = std::move(it->second);
  m.sessions.erase(it);
  for (auto& pending : state.publish_queue) {
    m.fault(std::move(pending), status::BadSessionClosed);
  }
  for (const std::uint32_t id : state.subscriptions) {
    if (delete_subscriptions) {
      Subscription& sub = m.subscriptions.at(id);
      m.item_count -= sub.items.size();
      m.subscriptions.erase(id);
    } else {
      // Kept until their lifetime runs out (or TransferSubscriptions takes them).
      m.subscriptions.at(id).session.reset();
    }
  }
  m.deliver();
}

std::size_t SubscriptionService::subscription_count() const {
  return impl_->subscriptions.size();
}

std::size_t SubscriptionService::monitored_item_count() const {
  return impl_->item_count;
}

std::size_t SubscriptionService::queued_publish_count(const SessionKey& session) const {
  const auto it = impl_->sessions.find(session);
  return it == impl_->sessions.end() ? 0 : it->second.publish_queue.size();
}

const SubscriptionLimits& SubscriptionService::limits() const {
  return impl_->limits;
}

}  // namespace sf::opcua
