// MonitoredItem service set: sampling, queues, filters, monitoring modes, timestamps, limits.
#include "fixture.hpp"

namespace sf::opcua::subs_test {
namespace {

using SubsMonitoredItems = SubscriptionsTest;

ExtensionObject data_change(DataChangeTrigger trigger, std::uint32_t deadband_type = 0, double deadband = 0) {
  DataChangeFilter f;
  f.trigger = trigger;
  f.deadband_type = deadband_type;
  f.deadband_value = deadband;
  return ExtensionObject::make(f);
}

std::vector<std::uint32_t> statuses(const PublishResponse& r) {
  std::vector<std::uint32_t> out;
  for (const auto& n : SubscriptionsTest::data(r)) {
    out.push_back(n.value.status.value());
  }
  return out;
}

TEST_F(SubsMonitoredItems, InitialValueAndChangesBatchedPerPublishingInterval) {
  set(node("T"), 1.0);
  const auto sub = create_sub(100, 10, 30);
  const auto item = create_item(sub, item_request(node("T"), params(7, 50, 5)));
  EXPECT_NE(item.monitored_item_id, 0U);
  EXPECT_EQ(item.revised_sampling_interval, 50);
  EXPECT_EQ(item.revised_queue_size, 5U);
  publish(1);
  advance(20);
  set(node("T"), 2.0);
  advance(40);  // sampled at 50
  set(node("T"), 3.0);
  EXPECT_TRUE(answers.empty());
  advance(40);  // sampled at 100, then the publishing cycle
  ASSERT_EQ(answers.size(), 1U);
  const auto& r = response(0);
  EXPECT_EQ(doubles(r), (Pairs{{7, 1.0}, {7, 2.0}, {7, 3.0}}));
  EXPECT_EQ(r.notification_message.sequence_number, 1U);
  EXPECT_EQ(r.available_sequence_numbers, (Array<std::uint32_t>{1}));
  EXPECT_EQ(statuses(r), (std::vector<std::uint32_t>{0, 0, 0}));
  EXPECT_EQ(r.notification_message.publish_time, DateTime::from_system_clock(clock.utc_now()));
}

TEST_F(SubsMonitoredItems, UnchangedValuesAreNotReported) {
  set(node("T"), 1.0);
  const auto sub = create_sub(100, 2, 30);
  create_item(sub, item_request(node("T"), params(7, 10, 5)));
  publish(1);
  advance(100);
  ASSERT_EQ(answers.size(), 1U);
  EXPECT_EQ(doubles(response(0)), (Pairs{{7, 1.0}}));
  publish(2);
  advance(200);  // ten samples of the same value, then a keep-alive
  ASSERT_EQ(answers.size(), 2U);
  EXPECT_TRUE(is_keep_alive(response(1)));
  EXPECT_EQ(response(1).notification_message.sequence_number, 2U);
}

// Five changes sampled into a queue of three between two publishing cycles.
class SubsQueueOverflow : public SubscriptionsTest {
 protected:
  PublishResponse run(std::uint32_t queue, bool discard_oldest) {
    set(node("T"), 0.0);
    const auto sub = create_sub(100, 10, 30);
    const auto r = create_item(sub, item_request(node("T"), params(3, 10, queue, discard_oldest)));
    revised_queue = r.revised_queue_size;
    for (int i = 1; i <= 5; ++i) {
      advance(5);
      set(node("T"), static_cast<double>(i));
      advance(5);
    }
    publish(1);
    advance(50);
    return answers.size() == 1 ? response(0) : PublishResponse{};
  }
  std::uint32_t revised_queue = 0;
};

TEST_F(SubsQueueOverflow, DiscardOldestSetsOverflowOnTheNextValue) {
  const auto r = run(3, true);
  EXPECT_EQ(doubles(r), (Pairs{{3, 3.0}, {3, 4.0}, {3, 5.0}}));
  EXPECT_EQ(statuses(r), (std::vector<std::uint32_t>{kOverflow, 0, 0}));
}

TEST_F(SubsQueueOverflow, DiscardNewestReplacesTheLastValueAndFlagsIt) {
  const auto r = run(3, false);
  EXPECT_EQ(doubles(r), (Pairs{{3, 0.0}, {3, 1.0}, {3, 5.0}}));
  EXPECT_EQ(statuses(r), (std::vector<std::uint32_t>{0, 0, kOverflow}));
}

TEST_F(SubsQueueOverflow, QueueOfOneKeepsTheNewestWithoutOverflowBit) {
  const auto r = run(0, false);
  EXPECT_EQ(revised_queue, 1U);
  EXPECT_EQ(doubles(r), (Pairs{{3, 5.0}}));
  EXPECT_EQ(statuses(r), (std::vector<std::uint32_t>{0}));
}

// Feeds values one per 10 ms sample and returns what one publish reports.
class SubsDeadband : public SubscriptionsTest {
 protected:
  Pairs feed(const std::vector<double>& values, ExtensionObject filter) {
    set(node("T"), values.at(0));
    const auto sub = create_sub(1000, 10, 30);
    create_item(sub, item_request(node("T"), params(1, 10, 100, true, std::move(filter))));
    for (std::size_t i = 1; i < values.size(); ++i) {
      advance(5);
      set(node("T"), values[i]);
      advance(5);
    }
    publish(1);
    advance(2000);
    return answers.empty() ? Pairs{} : doubles(response(0));
  }
};

TEST_F(SubsDeadband, AbsoluteComparesWithTheLastReportedValue) {
  EXPECT_EQ(feed({10, 10.5, 11.1, 11.5, 12.2, 11.3}, data_change(DataChangeTrigger::StatusValue, 1, 1.0)),
            (Pairs{{1, 10}, {1, 11.1}, {1, 12.2}}));
}

TEST_F(SubsDeadband, PercentUsesTheEuRange) {
  nodes[node("T")].eu_range = Range{-100, 100};  // 5 % of 200 = 10
  EXPECT_EQ(feed({100, 105, 110, 111, 115, 121.5}, data_change(DataChangeTrigger::StatusValue, 2, 5.0)),
            (Pairs{{1, 100}, {1, 111}, {1, 121.5}}));
}

TEST_F(SubsDeadband, ArraysReportWhenAnyElementOrTheSizeChanges) {
  set(node("A"), Variant(std::vector<double>{1, 2, 3}));
  const auto sub = create_sub(1000, 10, 30);
  create_item(sub, item_request(node("A"),
                                params(1, 10, 100, true, data_change(DataChangeTrigger::StatusValue, 1, 1))));
  const std::vector<std::vector<double>> steps = {{1.5, 2, 3}, {1, 2, 4.5}, {1, 2, 4.5}, {1, 2}};
  for (const auto& v : steps) {
    advance(5);
    set(node("A"), Variant(v));
    advance(5);
  }
  publish(1);
  advance(2000);
  ASSERT_EQ(answers.size(), 1U);
  const auto items = data(response(0));
  ASSERT_EQ(items.size(), 3U);
  EXPECT_EQ(*items[0].value.value.array_if<double>(), (Array<double>{1, 2, 3}));
  EXPECT_EQ(*items[1].value.value.array_if<double>(), (Array<double>{1, 2, 4.5}));
  EXPECT_EQ(*items[2].value.value.array_if<double>(), (Array<double>{1, 2}));
}

TEST_F(SubsMonitoredItems, FilterErrors) {
  set(node("T"), 1.0);
  set(node("S"), Variant("text"));
  const auto sub = create_sub();
  auto status_of = [&](const NodeId& n, ExtensionObject filter, std::uint32_t attribute = kValue) {
    auto r = create_items(sub, {item_request(n, params(1, -1, 1, true, std::move(filter)),
                                             MonitoringMode::Reporting, attribute)});
    EXPECT_EQ(r.response_header.service_result, status::Good);
    return r.results.at(0).status_code;
  };
  EXPECT_EQ(status_of(node("S"), data_change(DataChangeTrigger::StatusValue, 1, 1)),
            status::BadFilterNotAllowed);
  EXPECT_EQ(status_of(node("T"), data_change(DataChangeTrigger::StatusValue, 2, 5)),
            status::BadMonitoredItemFilterUnsupported);  // no EURange
  EXPECT_EQ(status_of(node("T"), data_change(DataChangeTrigger::StatusValue, 3, 1)),
            status::BadDeadbandFilterInvalid);
  EXPECT_EQ(status_of(node("T"), data_change(DataChangeTrigger::StatusValue, 1, -1)),
            status::BadDeadbandFilterInvalid);
  nodes[node("T")].eu_range = Range{0, 10};
  EXPECT_EQ(status_of(node("T"), data_change(DataChangeTrigger::StatusValue, 2, 150)),
            status::BadDeadbandFilterInvalid);
  EXPECT_EQ(status_of(node("T"), data_change(static_cast<DataChangeTrigger>(7))),
            status::BadMonitoredItemFilterInvalid);
  EXPECT_EQ(status_of(node("T"), data_change(DataChangeTrigger::Status), kBrowseName),
            status::BadFilterNotAllowed);
  EXPECT_EQ(status_of(node("T"), ExtensionObject::make(EventFilter{})), status::BadFilterNotAllowed);
  EXPECT_EQ(status_of(node("T"), ExtensionObject::make(Range{1, 2})),
            status::BadMonitoredItemFilterUnsupported);
  // A deadband on a string item is refused, a plain filter is fine.
  EXPECT_EQ(status_of(node("S"), data_change(DataChangeTrigger::StatusValueTimestamp)), status::Good);
  EXPECT_EQ(svc->monitored_item_count(), 1U);
}

TEST_F(SubsMonitoredItems, TriggerStatusIgnoresValueChanges) {
  set(node("T"), 1.0);
  const auto sub = create_sub(1000, 10, 30);
  create_item(sub, item_request(node("T"), params(1, 10, 10, true, data_change(DataChangeTrigger::Status))));
  advance(10);
  set(node("T"), 2.0);
  advance(10);
  set(node("T"), 3.0, status::UncertainLastUsableValue);
  advance(10);
  publish(1);
  advance(1000);
  ASSERT_EQ(answers.size(), 1U);
  EXPECT_EQ(doubles(response(0)), (Pairs{{1, 1.0}, {1, 3.0}}));
  EXPECT_EQ(statuses(response(0)), (std::vector<std::uint32_t>{0, status::UncertainLastUsableValue.value()}));
}

TEST_F(SubsMonitoredItems, TriggerStatusValueTimestampReportsNewSourceTimestamps) {
  set(node("A"), 1.0, {}, DateTime(1000));
  set(node("B"), 1.0, {}, DateTime(1000));
  const auto sub = create_sub(1000, 10, 30);
  create_item(sub, item_request(node("A"), params(1, 10, 10, true,
                                                  data_change(DataChangeTrigger::StatusValueTimestamp))));
  create_item(sub, item_request(node("B"), params(2, 10, 10)));  // default trigger StatusValue
  advance(15);
  set(node("A"), 1.0, {}, DateTime(2000));
  set(node("B"), 1.0, {}, DateTime(2000));
  publish(1);
  advance(1000);
  ASSERT_EQ(answers.size(), 1U);
  const auto items = data(response(0));
  ASSERT_EQ(items.size(), 3U);
  EXPECT_EQ(items[0].client_handle, 1U);
  EXPECT_EQ(items[1].client_handle, 1U);
  EXPECT_EQ(items[1].value.source_timestamp, DateTime(2000));
  EXPECT_EQ(items[2].client_handle, 2U);
  EXPECT_EQ(items[2].value.source_timestamp, DateTime(1000));
}

TEST_F(SubsMonitoredItems, TimestampsToReturnPerItem) {
  set(node("T"), 1.0, {}, DateTime(5000));
  const auto sub = create_sub(100, 10, 30);
  create_item(sub, item_request(node("T"), params(1)), TimestampsToReturn::Source);
  create_item(sub, item_request(node("T"), params(2)), TimestampsToReturn::Server);
  create_item(sub, item_request(node("T"), params(3)), TimestampsToReturn::Neither);
  create_item(sub, item_request(node("T"), params(4)), TimestampsToReturn::Both);
  publish(1);
  advance(100);
  ASSERT_EQ(answers.size(), 1U);
  const auto items = data(response(0));
  ASSERT_EQ(items.size(), 4U);
  const DateTime created = DateTime::from_system_clock(ManualClock().utc_now());
  EXPECT_EQ(items[0].value.source_timestamp, DateTime(5000));
  EXPECT_TRUE(items[0].value.server_timestamp.is_min());
  EXPECT_TRUE(items[1].value.source_timestamp.is_min());
  EXPECT_EQ(items[1].value.server_timestamp, created);
  EXPECT_TRUE(items[2].value.source_timestamp.is_min());
  EXPECT_TRUE(items[2].value.server_timestamp.is_min());
  EXPECT_EQ(items[3].value.source_timestamp, DateTime(5000));
  EXPECT_EQ(items[3].value.server_timestamp, created);
}

TEST_F(SubsMonitoredItems, SamplingModeQueuesAndReportingReportsTheQueue) {
  set(node("T"), 1.0);
  const auto sub = create_sub(100, 10, 30);
  const auto item = create_item(sub, item_request(node("T"), params(1, 10, 5), MonitoringMode::Sampling));
  publish(1);
  advance(100);
  ASSERT_EQ(answers.size(), 1U);
  EXPECT_TRUE(is_keep_alive(response(0)));
  set(node("T"), 2.0);
  advance(10);
  SetMonitoringModeRequest req;
  req.subscription_id = sub;
  req.monitoring_mode = MonitoringMode::Reporting;
  req.monitored_item_ids = {item.monitored_item_id, 555};
  const auto r = svc->set_monitoring_mode(session(), req);
  EXPECT_EQ(r.results, (Array<StatusCode>{status::Good, status::BadMonitoredItemIdInvalid}));
  publish(2);
  advance(90);
  ASSERT_EQ(answers.size(), 2U);
  EXPECT_EQ(doubles(response(1)), (Pairs{{1, 1.0}, {1, 2.0}}));
}

TEST_F(SubsMonitoredItems, DisabledItemsAreNotSampledAndReenablingReportsAtOnce) {
  set(node("T"), 1.0);
  const auto sub = create_sub(100, 10, 30);
  const auto item = create_item(sub, item_request(node("T"), params(1, 10, 5)));
  SetMonitoringModeRequest req;
  req.subscription_id = sub;
  req.monitoring_mode = MonitoringMode::Disabled;
  req.monitored_item_ids = {item.monitored_item_id};
  EXPECT_EQ(svc->set_monitoring_mode(session(), req).results, (Array<StatusCode>{status::Good}));
  const int reads_before = reads;
  set(node("T"), 2.0);
  publish(1);
  advance(100);
  EXPECT_EQ(reads, reads_before);
  ASSERT_EQ(answers.size(), 1U);
  EXPECT_TRUE(is_keep_alive(response(0)));  // the queued initial value went with Disabled
  set(node("T"), 3.0);
  req.monitoring_mode = MonitoringMode::Reporting;
  EXPECT_EQ(svc->set_monitoring_mode(session(), req).results, (Array<StatusCode>{status::Good}));
  publish(2);
  advance(100);
  ASSERT_EQ(answers.size(), 2U);
  EXPECT_EQ(doubles(response(1)), (Pairs{{1, 3.0}}));
  req.monitoring_mode = static_cast<MonitoringMode>(9);
  EXPECT_EQ(svc->set_monitoring_mode(session(), req).response_header.service_result,
            status::BadMonitoringModeInvalid);
}

TEST_F(SubsMonitoredItems, CreationErrors) {
  set(node("T"), 1.0);
  nodes[node("Obj")] = FakeNode{{}, true, false, {}};
  const auto sub = create_sub();
  auto r = create_items(sub, {item_request(node("Nope"), params(1)),
                              item_request(node("T"), params(2), MonitoringMode::Reporting, 0),
                              item_request(node("T"), params(3), MonitoringMode::Reporting, 99),
                              item_request(node("T"), params(4), static_cast<MonitoringMode>(5)),
                              item_request(node("T"), params(5), MonitoringMode::Reporting, kEventNotifier),
                              item_request(node("Obj"), params(6), MonitoringMode::Reporting, kEventNotifier),
                              item_request(node("T"), params(7))});
  EXPECT_EQ(r.response_header.service_result, status::Good);
  ASSERT_EQ(r.results.size(), 7U);
  EXPECT_EQ(r.results[0].status_code, status::BadNodeIdUnknown);
  EXPECT_EQ(r.results[1].status_code, status::BadAttributeIdInvalid);
  EXPECT_EQ(r.results[2].status_code, status::BadAttributeIdInvalid);
  EXPECT_EQ(r.results[3].status_code, status::BadMonitoringModeInvalid);
  EXPECT_EQ(r.results[4].status_code, status::BadAttributeIdInvalid);  // a variable has no EventNotifier
  EXPECT_EQ(r.results[5].status_code, status::BadNotReadable);         // not an event notifier
  EXPECT_EQ(r.results[6].status_code, status::Good);
  EXPECT_EQ(r.results[0].monitored_item_id, 0U);
  EXPECT_EQ(svc->monitored_item_count(), 1U);

  EXPECT_EQ(create_items(sub, {}).response_header.service_result, status::BadNothingToDo);
  EXPECT_EQ(create_items(sub, {item_request(node("T"), params(1))}, static_cast<TimestampsToReturn>(4))
                .response_header.service_result,
            status::BadTimestampsToReturnInvalid);
  EXPECT_EQ(create_items(999, {item_request(node("T"), params(1))}).response_header.service_result,
            status::BadSubscriptionIdInvalid);
}

TEST_F(SubsMonitoredItems, NonFatalReadErrorsAreReportedAsTheValue) {
  set(node("T"), Variant{}, status::BadWaitingForInitialData);
  const auto sub = create_sub(100, 10, 30);
  create_item(sub, item_request(node("T"), params(1)));
  publish(1);
  advance(100);
  ASSERT_EQ(answers.size(), 1U);
  EXPECT_EQ(statuses(response(0)), (std::vector<std::uint32_t>{status::BadWaitingForInitialData.value()}));
}

TEST_F(SubsMonitoredItems, ItemLimits) {
  SubscriptionLimits limits;
  limits.max_monitored_items_per_subscription = 2;
  limits.max_monitored_items = 3;
  limits.max_operations_per_request = 3;
  make(limits);
  set(node("T"), 1.0);
  const auto a = create_sub();
  const auto b = create_sub();
  auto r = create_items(a, {item_request(node("T"), params(1)), item_request(node("T"), params(2)),
                            item_request(node("T"), params(3))});
  ASSERT_EQ(r.results.size(), 3U);
  EXPECT_EQ(r.results[2].status_code, status::BadTooManyMonitoredItems);
  r = create_items(b, {item_request(node("T"), params(4)), item_request(node("T"), params(5))});
  EXPECT_EQ(r.results[0].status_code, status::Good);
  EXPECT_EQ(r.results[1].status_code, status::BadTooManyMonitoredItems);  // 3 in all
  EXPECT_EQ(svc->monitored_item_count(), 3U);
  r = create_items(b, std::vector<MonitoredItemCreateRequest>(4, item_request(node("T"), params(1))));
  EXPECT_EQ(r.response_header.service_result, status::BadTooManyOperations);
  EXPECT_TRUE(r.results.empty());
}

TEST_F(SubsMonitoredItems, RevisesSamplingIntervalAndQueueSize) {
  set(node("T"), 1.0);
  const auto sub = create_sub(250);
  auto r = create_items(sub, {item_request(node("T"), params(1, -1)), item_request(node("T"), params(2, 0)),
                              item_request(node("T"), params(3, 5)), item_request(node("T"), params(4, 1e9)),
                              item_request(node("T"), params(5, 40, 5000))});
  ASSERT_EQ(r.results.size(), 5U);
  EXPECT_EQ(r.results[0].revised_sampling_interval, 250);  // the publishing interval
  EXPECT_EQ(r.results[1].revised_sampling_interval, 10);   // fastest
  EXPECT_EQ(r.results[2].revised_sampling_interval, 10);
  EXPECT_EQ(r.results[3].revised_sampling_interval, 3'600'000);
  EXPECT_EQ(r.results[4].revised_sampling_interval, 40);
  EXPECT_EQ(r.results[4].revised_queue_size, 1000U);
}

TEST_F(SubsMonitoredItems, ModifyChangesHandleQueueAndFilter) {
  set(node("T"), 0.0);
  const auto sub = create_sub(1000, 10, 30);
  const auto item = create_item(sub, item_request(node("T"), params(1, 10, 5)));
  for (int i = 1; i <= 3; ++i) {
    advance(5);
    set(node("T"), static_cast<double>(i));
    advance(5);
  }
  ModifyMonitoredItemsRequest req;
  req.subscription_id = sub;
  req.timestamps_to_return = TimestampsToReturn::Both;
  MonitoredItemModifyRequest m;
  m.monitored_item_id = item.monitored_item_id;
  m.requested_parameters = params(8, 20, 2);
  req.items_to_modify = {m};
  m.monitored_item_id = 4711;
  req.items_to_modify.push_back(m);
  auto r = svc->modify_monitored_items(session(), req);
  ASSERT_EQ(r.results.size(), 2U);
  EXPECT_EQ(r.results[0].status_code, status::Good);
  EXPECT_EQ(r.results[0].revised_sampling_interval, 20);
  EXPECT_EQ(r.results[0].revised_queue_size, 2U);
  EXPECT_EQ(r.results[1].status_code, status::BadMonitoredItemIdInvalid);

  // A bad filter leaves the item as it was.
  req.items_to_modify = {req.items_to_modify[0]};
  req.items_to_modify[0].monitored_item_id = item.monitored_item_id;
  req.items_to_modify[0].requested_parameters =
      params(9, 20, 2, true, data_change(DataChangeTrigger::StatusValue, 3));
  r = svc->modify_monitored_items(session(), req);
  EXPECT_EQ(r.results.at(0).status_code, status::BadDeadbandFilterInvalid);

  publish(1);
  advance(1000);
  ASSERT_EQ(answers.size(), 1U);
  // Queue [0 1 2 3] shrunk to the newest two, the first flagged; the new handle is used.
  EXPECT_EQ(doubles(response(0)), (Pairs{{8, 2.0}, {8, 3.0}}));
  EXPECT_EQ(statuses(response(0)), (std::vector<std::uint32_t>{kOverflow, 0}));
}

TEST_F(SubsMonitoredItems, DeleteMonitoredItems) {
  set(node("T"), 1.0);
  const auto sub = create_sub(100, 10, 30);
  const auto a = create_item(sub, item_request(node("T"), params(1)));
  const auto b = create_item(sub, item_request(node("T"), params(2)));
  DeleteMonitoredItemsRequest req;
  req.subscription_id = sub;
  req.monitored_item_ids = {a.monitored_item_id, a.monitored_item_id};
  const auto r = svc->delete_monitored_items(session(), req);
  EXPECT_EQ(r.results, (Array<StatusCode>{status::Good, status::BadMonitoredItemIdInvalid}));
  EXPECT_EQ(svc->monitored_item_count(), 1U);
  publish(1);
  advance(100);
  ASSERT_EQ(answers.size(), 1U);
  EXPECT_EQ(doubles(response(0)), (Pairs{{2, 1.0}}));
  (void)b;
  req.monitored_item_ids = {};
  EXPECT_EQ(svc->delete_monitored_items(session(), req).response_header.service_result,
            status::BadNothingToDo);
}

}  // namespace
}  // namespace sf::opcua::subs_test
