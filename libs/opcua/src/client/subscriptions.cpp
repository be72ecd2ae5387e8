// Subscriptions and monitored items on the client side (OPC 10000-4 §5.12, §5.13), and their
// re-creation on a new session (§6.7): same client handles, same callbacks, new server ids.
#include <memory>

#include "client_impl.hpp"

namespace sf::opcua {

CreateSubscriptionRequest Client::Impl::subscription_request(const SubscriptionParams& params) {
  CreateSubscriptionRequest request;
  request.requested_publishing_interval = params.publishing_interval_ms;
  request.requested_lifetime_count = params.lifetime_count;
  request.requested_max_keep_alive_count = params.max_keep_alive_count;
  request.max_notifications_per_publish = params.max_notifications_per_publish;
  request.publishing_enabled = true;
  request.priority = params.priority;
  return request;
}

void Client::Impl::create_subscription(SubscriptionParams params,
                                       std::function<void(Result<SubscriptionId>)> done) {
  if (auto error = check_connected("CreateSubscription")) {
    fail_later(std::move(done), *error);
    return;
  }
  const std::uint64_t epoch = session_epoch;
  send(subscription_request(params),
       [this, params, epoch, done = std::move(done)](Result<CreateSubscriptionResponse> response) {
         if (!response) {
           done(client_detail::error_of(response));
           return;
         }
         if (epoch != session_epoch) {
           done(status_error(status::BadSessionClosed, "CreateSubscription: the session was replaced"));
           return;
         }
         Subscription sub;
         sub.id = next_subscription_id++;
         sub.params = params;
         sub.server_id = response->subscription_id;
         sub.revised_interval_ms = response->revised_publishing_interval;
         sub.revised_keep_alive = response->revised_max_keep_alive_count;
         const SubscriptionId id = sub.id;
         logger->debug("opcua client: subscription {} created (server id {}, {} ms)", id, sub.server_id,
                       sub.revised_interval_ms);
         subscriptions.emplace(id, std::move(sub));
         pump_publish();
         done(id);
       });
}

void Client::Impl::add_monitored_item(SubscriptionId subscription, MonitoredItem item, MonitorDone done) {
  if (auto error = check_connected("CreateMonitoredItems")) {
    fail_later(std::move(done), *error);
    return;
  }
  auto it = subscriptions.find(subscription);
  if (it == subscriptions.end() || it->second.server_id == 0) {
    fail_later(std::move(done),
               status_error(status::BadSubscriptionIdInvalid,
                            fmt::format("CreateMonitoredItems: no subscription {}", subscription)));
    return;
  }
  const std::uint32_t handle = next_client_handle++;
  if (next_client_handle == 0) {
    next_client_handle = 1;
  }
  item.client_handle = handle;
  item.parameters.client_handle = handle;

  CreateMonitoredItemsRequest request;
  request.subscription_id = it->second.server_id;
  request.timestamps_to_return = TimestampsToReturn::Both;
  request.items_to_create.push_back(
      MonitoredItemCreateRequest{item.item, MonitoringMode::Reporting, item.parameters});
  // Registered before the request goes out: the first notification may overtake the response.
  it->second.items.emplace(handle, std::move(item));

  const std::uint64_t epoch = session_epoch;
  send(std::move(request), [this, subscription, handle, epoch,
                            done = std::move(done)](Result<CreateMonitoredItemsResponse> response) {
    auto sub = subscriptions.find(subscription);
    if (sub == subscriptions.end()) {
      done(status_error(status::BadSubscriptionIdInvalid, "CreateMonitoredItems: subscription deleted"));
      return;
    }
    auto entry = sub->second.items.find(handle);
    if (entry == sub->second.items.end()) {
      done(status_error(status::BadMonitoredItemIdInvalid, "CreateMonitoredItems: item deleted"));
      return;
    }
    auto fail = [&](Error error) {
      sub->second.items.erase(entry);
      done(std::move(error));
    };
    if (!response) {
      fail(client_detail::error_of(response));
      return;
    }
    if (epoch != session_epoch) {
      fail(status_error(status::BadSessionClosed, "CreateMonitoredItems: the session was replaced"));
      return;
    }
    if (response->results.size() != 1) {
      logger->warn("opcua client: CreateMonitoredItems returned {} results for 1 item",
                   response->results.size());
      fail(status_error(status::BadUnknownResponse, "CreateMonitoredItems: wrong number of results"));
      return;
    }
    const MonitoredItemCreateResult& result = response->results.front();
    if (result.status_code.is_bad()) {
      fail(status_error(result.status_code, "CreateMonitoredItems"));
      return;
    }
    entry->second.server_id = result.monitored_item_id;
    entry->second.created = true;
    done(handle);
  });
}

void Client::Impl::unmonitor(SubscriptionId subscription, std::uint32_t client_handle,
                             std::function<void(Status)> done) {
  auto sub = subscriptions.find(subscription);
  if (sub == subscriptions.end()) {
    fail_later<void>(std::move(done), status_error(status::BadSubscriptionIdInvalid,
                                                   fmt::format("no subscription {}", subscription)));
    return;
  }
  auto entry = sub->second.items.find(client_handle);
  if (entry == sub->second.items.end()) {
    fail_later<void>(std::move(done), status_error(status::BadMonitoredItemIdInvalid,
                                                   fmt::format("no monitored item {}", client_handle)));
    return;
  }
  const std::uint32_t server_item = entry->second.created ? entry->second.server_id : 0;
  sub->second.items.erase(entry);
  if (server_item == 0 || sub->second.server_id == 0 || check_connected("DeleteMonitoredItems")) {
    post([done = std::move(done)]() { done({}); });
    return;
  }
  DeleteMonitoredItemsRequest request;
  request.subscription_id = sub->second.server_id;
  request.monitored_item_ids.push_back(server_item);
  send(std::move(request), [done = std::move(done)](Result<DeleteMonitoredItemsResponse> response) {
    if (!response) {
      done(client_detail::error_of(response));
    } else if (response->results.size() == 1 && response->results.front().is_bad()) {
      done(status_error(response->results.front(), "DeleteMonitoredItems"));
    } else {
      done({});
    }
  });
}

void Client::Impl::delete_subscription(SubscriptionId subscription, std::function<void(Status)> done) {
  auto sub = subscriptions.find(subscription);
  if (sub == subscriptions.end()) {
    fail_later<void>(std::move(done), status_error(status::BadSubscriptionIdInvalid,
                                                   fmt::format("no subscription {}", subscription)));
    return;
  }
  const std::uint32_t server_id = sub->second.server_id;
  subscriptions.erase(sub);
  std::erase_if(pending_acks,
                [&](const SubscriptionAcknowledgement& ack) { return ack.subscription_id == server_id; });
  if (server_id == 0 || check_connected("DeleteSubscriptions")) {
    post([done = std::move(done)]() { done({}); });
    return;
  }
  DeleteSubscriptionsRequest request;
  request.subscription_ids.push_back(server_id);
  send(std::move(request), [done = std::move(done)](Result<DeleteSubscriptionsResponse> response) {
    if (!response) {
      done(client_detail::error_of(response));
    } else if (response->results.size() == 1 && response->results.front().is_bad()) {
      done(status_error(response->results.front(), "DeleteSubscriptions"));
    } else {
      done({});
    }
  });
}

void Client::Impl::recreate_subscriptions(std::function<void()> done) {
  if (subscriptions.empty()) {
    done();
    return;
  }
  auto remaining = std::make_shared<std::size_t>(subscriptions.size());
  auto one_done = [remaining, done = std::move(done)]() {
    if (--*remaining == 0) {
      done();
    }
  };
  std::vector<SubscriptionId> ids;
  for (const auto& [id, sub] : subscriptions) {
    ids.push_back(id);
  }
  for (const SubscriptionId id : ids) {
    recreate_subscription(id, one_done);
  }
}

void Client::Impl::recreate_subscription(SubscriptionId id, std::function<void()> done) {
  auto it = subscriptions.find(id);
  if (it == subscriptions.end()) {
    done();
    return;
  }
  Subscription& sub = it->second;
  // A new server subscription numbers its messages from 1 again.
  sub.server_id = 0;
  sub.last_delivered = 0;
  sub.ahead.clear();
  sub.republishing.clear();
  sub.lost.clear();
  sub.last_available.clear();
  for (auto& [handle, item] : sub.items) {
    item.server_id = 0;
  }
  const std::uint64_t epoch = session_epoch;
  send(subscription_request(sub.params),
       [this, id, epoch, done = std::move(done)](Result<CreateSubscriptionResponse> response) {
         auto entry = subscriptions.find(id);
         if (epoch != session_epoch || entry == subscriptions.end()) {
           done();
           return;
         }
         if (!response) {
           logger->error("opcua client {}: subscription {} not re-created: {}", config.endpoint_url, id,
                         response.error().message);
           done();
           return;
         }
         entry->second.server_id = response->subscription_id;
         entry->second.revised_interval_ms = response->revised_publishing_interval;
         entry->second.revised_keep_alive = response->revised_max_keep_alive_count;
         logger->info("opcua client {}: subscription {} re-created (server id {})", config.endpoint_url, id,
                      response->subscription_id);
         recreate_items(id, done);
       });
}

void Client::Impl::recreate_items(SubscriptionId id, std::function<void()> done) {
  Subscription& sub = subscriptions.at(id);
  CreateMonitoredItemsRequest request;
  request.subscription_id = sub.server_id;
  request.timestamps_to_return = TimestampsToReturn::Both;
  std::vector<std::uint32_t> handles;
  for (const auto& [handle, item] : sub.items) {
    if (item.created) {  // items still being created are left to their own request
      handles.push_back(handle);
      request.items_to_create.push_back(
          MonitoredItemCreateRequest{item.item, MonitoringMode::Reporting, item.parameters});
    }
  }
  if (handles.empty()) {
    done();
    return;
  }
  const std::uint64_t epoch = session_epoch;
  send(std::move(request), [this, id, epoch, handles = std::move(handles),
                            done = std::move(done)](Result<CreateMonitoredItemsResponse> response) {
    auto entry = subscriptions.find(id);
    if (epoch != session_epoch || entry == subscriptions.end()) {
      done();
      return;
    }
    if (!response || response->results.size() != handles.size()) {
      logger->error("opcua client {}: monitored items of subscription {} not re-created: {}",
                    config.endpoint_url, id,
                    response ? std::string("wrong number of results") : response.error().message);
      done();
      return;
    }
    for (std::size_t i = 0; i < handles.size(); ++i) {
      auto item = entry->second.items.find(handles[i]);
      const MonitoredItemCreateResult& result = response->results[i];
      if (item == entry->second.items.end()) {
        continue;
      }
      if (result.status_code.is_bad()) {
        logger->error("opcua client {}: monitored item {} not re-created: {}", config.endpoint_url,
                      handles[i], to_string(result.status_code));
        continue;
      }
      item->second.server_id = result.monitored_item_id;
    }
    done();
  });
}

}  // namespace sf::opcua
