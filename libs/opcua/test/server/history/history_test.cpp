// Historical Access: raw reads over sorted values (OPC 10000-11 §6.4.3.2) with continuation
// points and bounds, MemoryHistory recording Historizing variables, and the HistoryRead service's
// checks (OPC 10000-4 §5.10.3).
#include "sf/opcua/server/history.hpp"

#include <gtest/gtest.h>

#include "../address_space/space_fixture.hpp"

namespace sf::opcua::server::test {
namespace {

DateTime at(std::int64_t seconds) {
  return DateTime::from_unix_seconds(1'700'000'000 + seconds);
}

DataValue sample(std::int32_t value, std::int64_t seconds) {
  DataValue v{Variant(value)};
  v.source_timestamp = at(seconds);
  v.server_timestamp = at(seconds);
  return v;
}

std::vector<std::int32_t> ints(const std::vector<DataValue>& values) {
  std::vector<std::int32_t> out;
  for (const DataValue& v : values) {
    const auto* i = v.value.get_if<std::int32_t>();
    out.push_back(i != nullptr ? *i : -1);
  }
  return out;
}

// Values 0..9 at seconds 0..9, plus a second value (100) at second 5.
std::vector<DataValue> ten_values() {
  std::vector<DataValue> values;
  for (std::int32_t i = 0; i < 10; ++i) {
    values.push_back(sample(i, i));
    if (i == 5) {
      values.push_back(sample(100, 5));
    }
  }
  return values;
}

HistoryRawQuery query(std::int64_t start, std::int64_t end, std::uint32_t max = 0) {
  HistoryRawQuery q;
  q.node = NodeId(1, 7);
  q.start = start < 0 ? DateTime::min() : at(start);
  q.end = end < 0 ? DateTime::min() : at(end);
  q.max_values = max;
  return q;
}

// Reads everything, following continuation points; fails the test on a bad status.
std::vector<std::int32_t> read_all(HistoryRawQuery q, const std::vector<DataValue>& values, int& calls) {
  std::vector<std::int32_t> out;
  calls = 0;
  do {
    HistoryRawResult r = read_raw_sorted(q, values);
    EXPECT_FALSE(r.status.is_bad()) << to_string(r.status);
    ++calls;
    for (std::int32_t v : ints(r.values)) {
      out.push_back(v);
    }
    q.continuation_point = r.continuation_point;
  } while (!q.continuation_point.is_null() && calls < 100);
  return out;
}

TEST(HistoryRaw, ForwardIsStartInclusiveEndExclusive) {
  const auto values = ten_values();
  EXPECT_EQ(ints(read_raw_sorted(query(2, 6), values).values), (std::vector<std::int32_t>{2, 3, 4, 5, 100}));
  // start == end: the values at that instant.
  EXPECT_EQ(ints(read_raw_sorted(query(5, 5), values).values), (std::vector<std::int32_t>{5, 100}));
  // Only a start: that many values from it.
  EXPECT_EQ(ints(read_raw_sorted(query(8, -1, 5), values).values), (std::vector<std::int32_t>{8, 9}));
  EXPECT_EQ(read_raw_sorted(query(20, 30), values).status, StatusCode(status::GoodNoData));
}

TEST(HistoryRaw, BackwardIsNewestFirst) {
  const auto values = ten_values();
  // start > end: end < t <= start.
  EXPECT_EQ(ints(read_raw_sorted(query(6, 2), values).values), (std::vector<std::int32_t>{6, 100, 5, 4, 3}));
  // Only an end: t <= end, newest first.
  EXPECT_EQ(ints(read_raw_sorted(query(-1, 3, 2), values).values), (std::vector<std::int32_t>{3, 2}));
}

TEST(HistoryRaw, ContinuationPointsSplitEqualTimestampsCorrectly) {
  const auto values = ten_values();
  for (std::uint32_t page : {1U, 2U, 3U, 4U}) {
    int calls = 0;
    EXPECT_EQ(read_all(query(0, 10, page), values, calls),
              (std::vector<std::int32_t>{0, 1, 2, 3, 4, 5, 100, 6, 7, 8, 9}))
        << "page " << page;
    EXPECT_EQ(calls, static_cast<int>((11 + page - 1) / page)) << "page " << page;
    EXPECT_EQ(read_all(query(9, -1, page), values, calls).size(), 1U);
    EXPECT_EQ(read_all(query(10, 0, page), values, calls),
              (std::vector<std::int32_t>{9, 8, 7, 6, 100, 5, 4, 3, 2, 1}))
        << "backwards, page " << page;
  }
}

TEST(HistoryRaw, ForeignOrCorruptContinuationPointsAreInvalid) {
  const auto values = ten_values();
  HistoryRawResult first = read_raw_sorted(query(0, 10, 3), values);
  ASSERT_FALSE(first.continuation_point.is_null());
  HistoryRawQuery other = query(0, 10, 3);
  other.node = NodeId(1, 8);
  other.continuation_point = first.continuation_point;
  EXPECT_EQ(read_raw_sorted(other, values).status, StatusCode(status::BadContinuationPointInvalid));
  HistoryRawQuery corrupt = query(0, 10, 3);
  corrupt.continuation_point = ByteString{1, 2, 3};
  EXPECT_EQ(read_raw_sorted(corrupt, values).status, StatusCode(status::BadContinuationPointInvalid));
}

TEST(HistoryRaw, BoundingValues) {
  const auto values = ten_values();
  HistoryRawQuery q = query(2, 4);
  q.return_bounds = true;
  // The start bound is the value at 2 itself; the end bound the first value at or after 4.
  EXPECT_EQ(ints(read_raw_sorted(q, values).values), (std::vector<std::int32_t>{2, 3, 4}));
  q = query(8, 20);
  q.return_bounds = true;
  HistoryRawResult r = read_raw_sorted(q, values);
  ASSERT_EQ(r.values.size(), 3U);
  EXPECT_EQ(r.values.back().status, StatusCode(status::BadBoundNotFound));
  EXPECT_EQ(r.values.back().source_timestamp, at(20));
}

class HistoryService : public SpaceFixture {
 protected:
  void SetUp() override {
    SpaceFixture::SetUp();
    auto* v = space.find_mutable_as<VariableNode>(counter);
    v->historizing = true;
    v->access_level = access_level::ReadWrite | access_level::HistoryRead;
    v->user_access_level = v->access_level;
    history.attach(space);
    for (std::int32_t i = 1; i <= 5; ++i) {
      DataValue value{Variant(i)};
      value.source_timestamp = at(i);
      value.server_timestamp = at(i + 100);
      ASSERT_TRUE(space.set_value(counter, value));
    }
  }
  void TearDown() override { history.detach(); }

  HistoryReadRequest request_for(const NodeId& node,
                                 TimestampsToReturn timestamps = TimestampsToReturn::Both) {
    HistoryReadRequest r;
    ReadRawModifiedDetails details;
    details.start_time = at(0);
    details.end_time = at(10);
    r.history_read_details = ExtensionObject::make(details);
    r.timestamps_to_return = timestamps;
    HistoryReadValueId item;
    item.node_id = node;
    r.nodes_to_read = Array<HistoryReadValueId>{item};
    return r;
  }

  MemoryHistory history;
};

TEST_F(HistoryService, ReturnsTheRecordedValuesWithTheRequestedTimestamps) {
  auto response = history_read(space, request_for(counter, TimestampsToReturn::Source), ctx, &history);
  ASSERT_EQ(response.response_header.service_result, StatusCode{});
  ASSERT_EQ(response.results.size(), 1U);
  EXPECT_EQ(response.results[0].status_code, StatusCode{});
  const auto* data = response.results[0].history_data.get_if<HistoryData>();
  ASSERT_NE(data, nullptr);
  EXPECT_EQ(ints(data->data_values), (std::vector<std::int32_t>{1, 2, 3, 4, 5}));
  EXPECT_EQ(data->data_values[0].source_timestamp, at(1));
  EXPECT_TRUE(data->data_values[0].server_timestamp.is_min());
}

TEST_F(HistoryService, NodeChecks) {
  auto request = request_for(counter);
  HistoryReadValueId unknown;
  unknown.node_id = NodeId(ns, "Nope");
  HistoryReadValueId object;
  object.node_id = demo;
  HistoryReadValueId not_historical;
  not_historical.node_id = temperature;
  request.nodes_to_read.push_back(unknown);
  request.nodes_to_read.push_back(object);
  request.nodes_to_read.push_back(not_historical);
  auto response = history_read(space, request, ctx, &history);
  ASSERT_EQ(response.results.size(), 4U);
  EXPECT_EQ(response.results[1].status_code, StatusCode(status::BadNodeIdUnknown));
  EXPECT_EQ(response.results[2].status_code, StatusCode(status::BadHistoryOperationUnsupported));
  EXPECT_EQ(response.results[3].status_code, StatusCode(status::BadNotReadable));
  // Without a database every node is unsupported.
  auto none = history_read(space, request_for(counter), ctx, nullptr);
  EXPECT_EQ(none.results[0].status_code, StatusCode(status::BadHistoryOperationUnsupported));
}

TEST_F(HistoryService, RequestChecks) {
  auto neither = history_read(space, request_for(counter, TimestampsToReturn::Neither), ctx, &history);
  EXPECT_EQ(neither.response_header.service_result, StatusCode(status::BadTimestampsToReturnInvalid));
  auto modified = request_for(counter);
  ReadRawModifiedDetails details;
  details.is_read_modified = true;
  details.start_time = at(0);
  details.end_time = at(1);
  modified.history_read_details = ExtensionObject::make(details);
  EXPECT_EQ(history_read(space, modified, ctx, &history).response_header.service_result,
            StatusCode(status::BadHistoryOperationUnsupported));
  auto open = request_for(counter);
  open.history_read_details = ExtensionObject::make(ReadRawModifiedDetails{});
  EXPECT_EQ(history_read(space, open, ctx, &history).response_header.service_result,
            StatusCode(status::BadInvalidTimestampArgument));
  auto empty = request_for(counter);
  empty.nodes_to_read.clear();
  EXPECT_EQ(history_read(space, empty, ctx, &history).response_header.service_result,
            StatusCode(status::BadNothingToDo));
}

TEST_F(HistoryService, ReleasingContinuationPointsReturnsNoData) {
  auto request = request_for(counter);
  request.release_continuation_points = true;
  auto response = history_read(space, request, ctx, &history);
  ASSERT_EQ(response.results.size(), 1U);
  EXPECT_EQ(response.results[0].status_code, StatusCode{});
  EXPECT_TRUE(response.results[0].history_data.empty());
}

TEST(MemoryHistoryDepth, KeepsTheNewestValuesOnly) {
  MemoryHistory history(4);
  const NodeId node(1, 7);
  for (std::int32_t i = 0; i < 20; ++i) {
    history.record(node, sample(i, i));
  }
  HistoryRawQuery q = query(0, 100);
  q.node = node;
  EXPECT_EQ(ints(history.read_raw(q).values), (std::vector<std::int32_t>{16, 17, 18, 19}));
  // A late value goes to its place in time.
  history.record(node, sample(-5, 17));
  EXPECT_EQ(ints(history.read_raw(q).values), (std::vector<std::int32_t>{17, -5, 18, 19}));
}

}  // namespace
}  // namespace sf::opcua::server::test
