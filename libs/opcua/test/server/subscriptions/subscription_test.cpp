// Subscription service set: parameters, keep-alive, lifetime, the Publish queue, sessions.
#include <cmath>
#include <limits>

#include "fixture.hpp"

namespace sf::opcua::subs_test {
namespace {

using SubsLifecycle = SubscriptionsTest;

CreateSubscriptionRequest subscription_request(double interval, std::uint32_t keep_alive,
                                               std::uint32_t lifetime, std::uint32_t max_notifications = 0) {
  CreateSubscriptionRequest r;
  r.requested_publishing_interval = interval;
  r.requested_max_keep_alive_count = keep_alive;
  r.requested_lifetime_count = lifetime;
  r.max_notifications_per_publish = max_notifications;
  r.publishing_enabled = true;
  return r;
}

TEST_F(SubsLifecycle, RevisesParameters) {
  auto r = svc->create_subscription(session(), subscription_request(0, 0, 0));
  EXPECT_EQ(r.response_header.service_result, status::Good);
  EXPECT_NE(r.subscription_id, 0U);
  EXPECT_EQ(r.revised_publishing_interval, 10);   // fastest supported
  EXPECT_EQ(r.revised_max_keep_alive_count, 1U);  // smallest supported
  EXPECT_EQ(r.revised_lifetime_count, 3U);        // at least 3 x keep-alive

  r = svc->create_subscription(session(), subscription_request(5e6, 5, 7));
  EXPECT_EQ(r.revised_publishing_interval, 3'600'000);
  EXPECT_EQ(r.revised_max_keep_alive_count, 5U);
  EXPECT_EQ(r.revised_lifetime_count, 15U);

  r = svc->create_subscription(session(), subscription_request(std::nan(""), 20'000, 1'000'000));
  EXPECT_EQ(r.revised_publishing_interval, 10);
  EXPECT_EQ(r.revised_max_keep_alive_count, 10'000U);
  EXPECT_EQ(r.revised_lifetime_count, 30'000U);

  r = svc->create_subscription(session(), subscription_request(250, 10, 60));
  EXPECT_EQ(r.revised_publishing_interval, 250);
  EXPECT_EQ(r.revised_max_keep_alive_count, 10U);
  EXPECT_EQ(r.revised_lifetime_count, 60U);
  EXPECT_EQ(svc->subscription_count(), 4U);
}

TEST_F(SubsLifecycle, SubscriptionIdsAreDistinct) {
  const auto a = create_sub();
  const auto b = create_sub();
  const auto c = create_sub(100, 3, 30, 0, true, other_session());
  EXPECT_NE(a, b);
  EXPECT_NE(b, c);
  EXPECT_NE(a, c);
}

TEST_F(SubsLifecycle, FirstCycleSendsKeepAliveThenEveryMaxKeepAliveCount) {
  const auto sub = create_sub(100, 3, 30);
  publish(1);
  advance(99);
  EXPECT_TRUE(answers.empty());
  advance(1);
  ASSERT_EQ(answers.size(), 1U);
  EXPECT_EQ(answers[0].handle, 1U);
  const auto& first = response(0);
  EXPECT_EQ(first.subscription_id, sub);
  EXPECT_TRUE(is_keep_alive(first));
  EXPECT_EQ(first.notification_message.sequence_number, 1U);  // the next sequence number
  EXPECT_TRUE(first.available_sequence_numbers.empty());
  EXPECT_FALSE(first.more_notifications);
  EXPECT_EQ(first.response_header.service_result, status::Good);

  publish(2);
  advance(299);  // cycles at 200 and 300: nothing to send, keep-alive not due
  EXPECT_EQ(answers.size(), 1U);
  advance(1);  // third empty cycle at 400
  ASSERT_EQ(answers.size(), 2U);
  EXPECT_EQ(answers[1].handle, 2U);
  EXPECT_TRUE(is_keep_alive(response(1)));
  EXPECT_EQ(response(1).notification_message.sequence_number, 1U);
}

TEST_F(SubsLifecycle, LateSubscriptionAnswersTheNextPublishAtOnce) {
  create_sub(100, 3, 30);
  advance(250);  // first cycle at 100 wanted to send a keep-alive: late
  EXPECT_TRUE(answers.empty());
  publish(9);
  ASSERT_EQ(answers.size(), 1U);
  EXPECT_EQ(answers[0].handle, 9U);
  EXPECT_TRUE(is_keep_alive(response(0)));
  // Not late any more: the next Publish waits.
  publish(10);
  EXPECT_EQ(answers.size(), 1U);
  EXPECT_EQ(svc->queued_publish_count(session()), 1U);
}

TEST_F(SubsLifecycle, LifetimeExpirySendsStatusChangeAndDeletes) {
  const auto sub = create_sub(100, 1, 3);
  set(node("T"), 1.0);
  create_item(sub, item_request(node("T"), params(1)));
  EXPECT_EQ(svc->monitored_item_count(), 1U);
  advance(299);
  EXPECT_EQ(svc->subscription_count(), 1U);
  advance(1);  // third cycle without a Publish request
  EXPECT_EQ(svc->subscription_count(), 0U);
  EXPECT_EQ(svc->monitored_item_count(), 0U);

  publish(1);
  ASSERT_EQ(answers.size(), 1U);
  const auto& r = response(0);
  EXPECT_EQ(r.subscription_id, sub);
  EXPECT_EQ(r.notification_message.sequence_number, 1U);
  ASSERT_EQ(r.notification_message.notification_data.size(), 1U);
  const auto* change = r.notification_message.notification_data[0].get_if<StatusChangeNotification>();
  ASSERT_NE(change, nullptr);
  EXPECT_EQ(change->status, status::BadTimeout);
  EXPECT_TRUE(r.available_sequence_numbers.empty());

  publish(2);
  ASSERT_EQ(answers.size(), 2U);
  EXPECT_EQ(fault(1), status::BadNoSubscription);
}

TEST_F(SubsLifecycle, PublishRequestsKeepTheSubscriptionAlive) {
  create_sub(100, 1, 3);
  for (std::uint32_t i = 0; i < 10; ++i) {
    publish(i);
    advance(100);
    ASSERT_EQ(answers.size(), i + 1);
    EXPECT_TRUE(is_keep_alive(response(i)));
  }
  EXPECT_EQ(svc->subscription_count(), 1U);
}

TEST_F(SubsLifecycle, ServiceCallsResetTheLifetime) {
  const auto sub = create_sub(100, 1, 3);
  for (int i = 0; i < 5; ++i) {
    advance(200);
    SetPublishingModeRequest req;
    req.publishing_enabled = true;
    req.subscription_ids = {sub};
    EXPECT_EQ(svc->set_publishing_mode(session(), req).results.at(0), status::Good);
  }
  EXPECT_EQ(svc->subscription_count(), 1U);
  advance(300);
  EXPECT_EQ(svc->subscription_count(), 0U);
}

TEST_F(SubsLifecycle, PublishWithoutSubscriptionFails) {
  publish(4);
  ASSERT_EQ(answers.size(), 1U);
  EXPECT_EQ(answers[0].handle, 4U);
  EXPECT_EQ(fault(0), status::BadNoSubscription);
}

TEST_F(SubsLifecycle, TooManyPublishRequestsDropsTheOldest) {
  SubscriptionLimits limits;
  limits.max_publish_requests_per_session = 2;
  make(limits);
  create_sub(10'000, 3, 30);
  publish(1);
  publish(2);
  EXPECT_TRUE(answers.empty());
  publish(3);
  ASSERT_EQ(answers.size(), 1U);
  EXPECT_EQ(answers[0].handle, 1U);
  EXPECT_EQ(fault(0), status::BadTooManyPublishRequests);
  EXPECT_EQ(svc->queued_publish_count(session()), 2U);
}

TEST_F(SubsLifecycle, PublishTimesOutAfterItsTimeoutHint) {
  create_sub(10'000, 3, 30);
  publish(1, {}, 500);
  publish(2);  // no timeout hint: waits
  advance(499);
  EXPECT_TRUE(answers.empty());
  advance(1);
  ASSERT_EQ(answers.size(), 1U);
  EXPECT_EQ(answers[0].handle, 1U);
  EXPECT_EQ(fault(0), status::BadTimeout);
  EXPECT_EQ(svc->queued_publish_count(session()), 1U);
}

TEST_F(SubsLifecycle, CloseSessionAnswersQueuedPublishesAndDeletes) {
  create_sub(10'000);
  create_sub(10'000);
  publish(1);
  publish(2);
  svc->close_session(session(), true);
  ASSERT_EQ(answers.size(), 2U);
  EXPECT_EQ(fault(0), status::BadSessionClosed);
  EXPECT_EQ(fault(1), status::BadSessionClosed);
  EXPECT_EQ(svc->subscription_count(), 0U);
}

TEST_F(SubsLifecycle, ClosedSessionKeepsSubscriptionsUntilTheirLifetime) {
  create_sub(100, 1, 3);
  svc->close_session(session(), false);
  EXPECT_EQ(svc->subscription_count(), 1U);
  advance(299);
  EXPECT_EQ(svc->subscription_count(), 1U);
  advance(1);
  EXPECT_EQ(svc->subscription_count(), 0U);
  EXPECT_TRUE(answers.empty());
  publish(1);
  EXPECT_EQ(fault(0), status::BadNoSubscription);
}

TEST_F(SubsLifecycle, DeletingTheLastSubscriptionFailsQueuedPublishes) {
  const auto a = create_sub(10'000);
  const auto b = create_sub(10'000);
  publish(1);
  DeleteSubscriptionsRequest del;
  del.request_header = header(77);
  del.subscription_ids = {a, 4242};
  auto r = svc->delete_subscriptions(session(), del);
  EXPECT_EQ(r.response_header.request_handle, 77U);
  EXPECT_EQ(r.results, (Array<StatusCode>{status::Good, status::BadSubscriptionIdInvalid}));
  EXPECT_TRUE(answers.empty());  // b still there
  del.subscription_ids = {b};
  r = svc->delete_subscriptions(session(), del);
  EXPECT_EQ(r.results, (Array<StatusCode>{status::Good}));
  ASSERT_EQ(answers.size(), 1U);
  EXPECT_EQ(fault(0), status::BadNoSubscription);
  del.subscription_ids = {};
  EXPECT_EQ(svc->delete_subscriptions(session(), del).response_header.service_result, status::BadNothingToDo);
}

TEST_F(SubsLifecycle, SubscriptionsBelongToTheirSession) {
  const auto sub = create_sub(100, 3, 30);
  set(node("T"), 1.0);
  const auto item = create_item(sub, item_request(node("T"), params(1)));
  const SessionKey b = other_session();

  ModifySubscriptionRequest mod;
  mod.subscription_id = sub;
  EXPECT_EQ(svc->modify_subscription(b, mod).response_header.service_result,
            status::BadSubscriptionIdInvalid);
  SetPublishingModeRequest spm;
  spm.subscription_ids = {sub};
  EXPECT_EQ(svc->set_publishing_mode(b, spm).results, (Array<StatusCode>{status::BadSubscriptionIdInvalid}));
  EXPECT_EQ(create_items(sub, {item_request(node("T"), params(2))}, TimestampsToReturn::Both, b)
                .response_header.service_result,
            status::BadSubscriptionIdInvalid);
  DeleteMonitoredItemsRequest dmi;
  dmi.subscription_id = sub;
  dmi.monitored_item_ids = {item.monitored_item_id};
  EXPECT_EQ(svc->delete_monitored_items(b, dmi).response_header.service_result,
            status::BadSubscriptionIdInvalid);
  RepublishRequest rep;
  rep.subscription_id = sub;
  rep.retransmit_sequence_number = 1;
  EXPECT_EQ(svc->republish(b, rep).response_header.service_result, status::BadSubscriptionIdInvalid);
  DeleteSubscriptionsRequest del;
  del.subscription_ids = {sub};
  EXPECT_EQ(svc->delete_subscriptions(b, del).results, (Array<StatusCode>{status::BadSubscriptionIdInvalid}));

  publish(1, {{sub, 1}}, 0, b);
  ASSERT_EQ(answers.size(), 1U);
  EXPECT_EQ(fault(0), status::BadNoSubscription);
  EXPECT_EQ(svc->subscription_count(), 1U);
  EXPECT_EQ(svc->monitored_item_count(), 1U);
  // Session A's Publish still gets A's data.
  publish(2);
  advance(100);
  ASSERT_EQ(answers.size(), 2U);
  EXPECT_EQ(doubles(response(1)), (Pairs{{1, 1.0}}));
}

TEST_F(SubsLifecycle, SubscriptionLimits) {
  SubscriptionLimits limits;
  limits.max_subscriptions_per_session = 2;
  limits.max_subscriptions = 3;
  make(limits);
  create_sub();
  create_sub();
  CreateSubscriptionRequest req = subscription_request(100, 3, 30);
  req.request_header = header(5);
  auto r = svc->create_subscription(session(), req);
  EXPECT_EQ(r.response_header.service_result, status::BadTooManySubscriptions);
  EXPECT_EQ(r.response_header.request_handle, 5U);
  EXPECT_EQ(r.subscription_id, 0U);
  create_sub(100, 3, 30, 0, true, other_session());
  r = svc->create_subscription(other_session(), req);
  EXPECT_EQ(r.response_header.service_result, status::BadTooManySubscriptions);
  EXPECT_EQ(svc->subscription_count(), 3U);
}

TEST_F(SubsLifecycle, PublishingDisabledSendsOnlyKeepAlives) {
  set(node("T"), 1.0);
  const auto sub = create_sub(100, 2, 30, 0, /*enabled=*/false);
  create_item(sub, item_request(node("T"), params(1, 100)));
  publish(1);
  advance(100);
  ASSERT_EQ(answers.size(), 1U);
  EXPECT_TRUE(is_keep_alive(response(0)));
  set(node("T"), 2.0);
  publish(2);
  advance(200);  // keep-alive after 2 empty cycles
  ASSERT_EQ(answers.size(), 2U);
  EXPECT_TRUE(is_keep_alive(response(1)));

  SetPublishingModeRequest req;
  req.publishing_enabled = true;
  req.subscription_ids = {sub, 999};
  const auto r = svc->set_publishing_mode(session(), req);
  EXPECT_EQ(r.response_header.service_result, status::Good);
  EXPECT_EQ(r.results, (Array<StatusCode>{status::Good, status::BadSubscriptionIdInvalid}));
  publish(3);
  advance(100);
  ASSERT_EQ(answers.size(), 3U);
  // Items kept sampling while publishing was off; queue size 1 holds the newest value.
  EXPECT_EQ(doubles(response(2)), (Pairs{{1, 2.0}}));
  EXPECT_EQ(response(2).notification_message.sequence_number, 1U);
}

TEST_F(SubsLifecycle, ModifySubscriptionRevisesAndRestartsTheTimer) {
  const auto sub = create_sub(100, 3, 30);
  advance(50);
  ModifySubscriptionRequest req;
  req.request_header = header(3);
  req.subscription_id = sub;
  req.requested_publishing_interval = 200;
  req.requested_max_keep_alive_count = 2;
  req.requested_lifetime_count = 1;
  const auto r = svc->modify_subscription(session(), req);
  EXPECT_EQ(r.response_header.service_result, status::Good);
  EXPECT_EQ(r.response_header.request_handle, 3U);
  EXPECT_EQ(r.revised_publishing_interval, 200);
  EXPECT_EQ(r.revised_max_keep_alive_count, 2U);
  EXPECT_EQ(r.revised_lifetime_count, 6U);
  publish(1);
  advance(199);
  EXPECT_TRUE(answers.empty());
  advance(1);
  EXPECT_EQ(answers.size(), 1U);
  req.subscription_id = 777;
  EXPECT_EQ(svc->modify_subscription(session(), req).response_header.service_result,
            status::BadSubscriptionIdInvalid);
}

TEST_F(SubsLifecycle, NextDueFollowsCyclesSamplesAndTimeouts) {
  EXPECT_EQ(svc->next_due(), Clock::time_point::max());
  const auto start = clock.now();
  const auto sub = create_sub(100, 3, 30);
  EXPECT_EQ(svc->next_due(), start + std::chrono::milliseconds(100));
  set(node("T"), 1.0);
  create_item(sub, item_request(node("T"), params(1, 30)));
  EXPECT_EQ(svc->next_due(), start + std::chrono::milliseconds(30));
  publish(1, {}, 20);
  EXPECT_EQ(svc->next_due(), start + std::chrono::milliseconds(20));
}

TEST_F(SubsLifecycle, RespondCallbackMayPublishAgain) {
  create_sub(100, 1, 30);
  int answered = 0;
  std::function<void(Message)> respond = [&](Message m) {
    EXPECT_TRUE(std::holds_alternative<PublishResponse>(m));
    if (++answered < 3) {
      PublishRequest again;
      svc->publish(session(), again, respond);
    }
  };
  svc->publish(session(), PublishRequest{}, respond);
  advance(1000);
  EXPECT_EQ(answered, 3);
  EXPECT_EQ(svc->queued_publish_count(session()), 0U);
}

}  // namespace
}  // namespace sf::opcua::subs_test
