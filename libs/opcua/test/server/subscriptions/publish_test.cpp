// Publish: sequence numbers, acknowledgements, availableSequenceNumbers, Republish and
// moreNotifications.
#include "fixture.hpp"

namespace sf::opcua::subs_test {
namespace {

using SubsPublishing = SubscriptionsTest;

TEST_F(SubsPublishing, SequenceNumbersAcknowledgementsAndAvailableNumbers) {
  set(node("T"), 0.0);
  const auto sub = create_sub(100, 10, 30);
  create_item(sub, item_request(node("T"), params(1, 100)));
  publish(1);
  advance(100);
  ASSERT_EQ(answers.size(), 1U);
  EXPECT_EQ(response(0).notification_message.sequence_number, 1U);
  EXPECT_EQ(response(0).available_sequence_numbers, (Array<std::uint32_t>{1}));

  set(node("T"), 1.0);
  publish(2);
  advance(100);
  ASSERT_EQ(answers.size(), 2U);
  EXPECT_EQ(response(1).notification_message.sequence_number, 2U);
  EXPECT_EQ(response(1).available_sequence_numbers, (Array<std::uint32_t>{1, 2}));
  EXPECT_EQ(doubles(response(1)), (Pairs{{1, 1.0}}));

  set(node("T"), 2.0);
  publish(3, {{sub, 1}, {sub, 99}, {777, 1}, {sub, 1}});
  advance(100);
  ASSERT_EQ(answers.size(), 3U);
  const auto& third = response(2);
  EXPECT_EQ(third.results,
            (Array<StatusCode>{status::Good, status::BadSequenceNumberUnknown,
                               status::BadSubscriptionIdInvalid, status::BadSequenceNumberUnknown}));
  EXPECT_EQ(third.notification_message.sequence_number, 3U);
  EXPECT_EQ(third.available_sequence_numbers, (Array<std::uint32_t>{2, 3}));

  // A keep-alive carries the next sequence number and consumes none.
  publish(4, {{sub, 3}});
  advance(1000);
  ASSERT_EQ(answers.size(), 4U);
  EXPECT_TRUE(is_keep_alive(response(3)));
  EXPECT_EQ(response(3).notification_message.sequence_number, 4U);
  EXPECT_EQ(response(3).available_sequence_numbers, (Array<std::uint32_t>{2}));
  EXPECT_EQ(response(3).results, (Array<StatusCode>{status::Good}));

  set(node("T"), 3.0);
  publish(5);
  advance(100);
  ASSERT_EQ(answers.size(), 5U);
  EXPECT_EQ(response(4).notification_message.sequence_number, 4U);
}

TEST_F(SubsPublishing, RepublishReturnsUnacknowledgedMessages) {
  set(node("T"), 0.0);
  const auto sub = create_sub(100, 10, 30);
  create_item(sub, item_request(node("T"), params(1, 100)));
  for (int i = 1; i <= 3; ++i) {
    publish(static_cast<std::uint32_t>(i));
    advance(100);
    set(node("T"), static_cast<double>(i));
  }
  ASSERT_EQ(answers.size(), 3U);
  RepublishRequest req;
  req.request_header = header(42);
  req.subscription_id = sub;
  req.retransmit_sequence_number = 2;
  auto r = svc->republish(session(), req);
  EXPECT_EQ(r.response_header.service_result, status::Good);
  EXPECT_EQ(r.response_header.request_handle, 42U);
  EXPECT_EQ(r.notification_message, response(1).notification_message);

  publish(9, {{sub, 2}});
  r = svc->republish(session(), req);
  EXPECT_EQ(r.response_header.service_result, status::BadMessageNotAvailable);
  req.retransmit_sequence_number = 99;
  EXPECT_EQ(svc->republish(session(), req).response_header.service_result, status::BadMessageNotAvailable);
  req.subscription_id = 99;
  EXPECT_EQ(svc->republish(session(), req).response_header.service_result, status::BadSubscriptionIdInvalid);
}

TEST_F(SubsPublishing, RetransmissionQueueIsBounded) {
  SubscriptionLimits limits;
  limits.max_retransmission_queue = 2;
  make(limits);
  set(node("T"), 0.0);
  const auto sub = create_sub(100, 10, 30);
  create_item(sub, item_request(node("T"), params(1, 100)));
  for (int i = 1; i <= 3; ++i) {
    publish(static_cast<std::uint32_t>(i));
    advance(100);
    set(node("T"), static_cast<double>(i));
  }
  ASSERT_EQ(answers.size(), 3U);
  EXPECT_EQ(response(2).available_sequence_numbers, (Array<std::uint32_t>{2, 3}));
  RepublishRequest req;
  req.subscription_id = sub;
  req.retransmit_sequence_number = 1;
  EXPECT_EQ(svc->republish(session(), req).response_header.service_result, status::BadMessageNotAvailable);
}

TEST_F(SubsPublishing, MoreNotificationsWhenOverMaxNotificationsPerPublish) {
  const auto sub = create_sub(100, 10, 30, /*max_notifications=*/2);
  for (std::uint32_t h = 1; h <= 5; ++h) {
    const std::string name = "N" + std::to_string(h);
    set(NodeId(1, String(name)), static_cast<double>(h * 10));
    create_item(sub, item_request(NodeId(1, String(name)), params(h)));
  }
  publish(1);
  advance(100);
  ASSERT_EQ(answers.size(), 1U);
  EXPECT_EQ(doubles(response(0)), (Pairs{{1, 10}, {2, 20}}));
  EXPECT_TRUE(response(0).more_notifications);
  // The next Publish is answered at once while there are more notifications.
  publish(2);
  ASSERT_EQ(answers.size(), 2U);
  EXPECT_EQ(doubles(response(1)), (Pairs{{3, 30}, {4, 40}}));
  EXPECT_TRUE(response(1).more_notifications);
  publish(3);
  ASSERT_EQ(answers.size(), 3U);
  EXPECT_EQ(doubles(response(2)), (Pairs{{5, 50}}));
  EXPECT_FALSE(response(2).more_notifications);
  EXPECT_EQ(response(2).notification_message.sequence_number, 3U);
  EXPECT_EQ(response(2).available_sequence_numbers, (Array<std::uint32_t>{1, 2, 3}));
  publish(4);
  EXPECT_EQ(answers.size(), 3U);
  EXPECT_EQ(svc->queued_publish_count(session()), 1U);
}

TEST_F(SubsPublishing, SeveralSubscriptionsShareTheSessionsPublishRequests) {
  set(node("T"), 1.0);
  const auto a = create_sub(100, 10, 30);
  const auto b = create_sub(100, 10, 30);
  create_item(a, item_request(node("T"), params(1)));
  create_item(b, item_request(node("T"), params(2)));
  publish(1);
  advance(100);  // a takes the request, b goes late
  ASSERT_EQ(answers.size(), 1U);
  EXPECT_EQ(response(0).subscription_id, a);
  EXPECT_EQ(doubles(response(0)), (Pairs{{1, 1.0}}));
  publish(2);  // answered at once for the late b
  ASSERT_EQ(answers.size(), 2U);
  EXPECT_EQ(response(1).subscription_id, b);
  EXPECT_EQ(doubles(response(1)), (Pairs{{2, 1.0}}));
  EXPECT_EQ(response(1).notification_message.sequence_number, 1U);  // per subscription
}

TEST_F(SubsPublishing, TooManyAcknowledgementsAreRejected) {
  SubscriptionLimits limits;
  limits.max_operations_per_request = 2;
  make(limits);
  const auto sub = create_sub();
  publish(1, {{sub, 1}, {sub, 2}, {sub, 3}});
  ASSERT_EQ(answers.size(), 1U);
  EXPECT_EQ(fault(0), status::BadTooManyOperations);
}

}  // namespace
}  // namespace sf::opcua::subs_test

namespace sf::opcua::subs_test {
namespace {

// A server shutting down sends what its subscriptions hold without waiting for the interval.
TEST_F(SubsPublishing, FlushSendsHeldNotificationsAtOnce) {
  set(node("T"), 0.0);
  const auto sub = create_sub(1000, 10, 30);
  create_item(sub, item_request(node("T"), params(1, 10)));
  publish(1);
  advance(1000);
  ASSERT_EQ(answers.size(), 1U);  // the initial value
  set(node("T"), 5.0);
  publish(2);
  advance(10);  // sampled into the item's queue; the publishing interval is far off
  ASSERT_EQ(answers.size(), 1U);
  svc->flush();
  ASSERT_EQ(answers.size(), 2U);
  EXPECT_EQ(doubles(response(1)), (Pairs{{1, 5.0}}));
  // Nothing held: flush sends nothing (the queued request waits for the next cycle).
  publish(3);
  svc->flush();
  EXPECT_EQ(answers.size(), 2U);
}

}  // namespace
}  // namespace sf::opcua::subs_test
