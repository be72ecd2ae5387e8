// The store suite: every test runs against SQLite and against a real
// PostgreSQL server (started by the test binary; the PostgreSQL half skips
// with a message only when PostgreSQL is not installed).
#include <cmath>
#include <limits>

#include <gtest/gtest.h>

#include "make_sample.hpp"
#include "sf/historian/store.hpp"
#include "store_backends.hpp"

namespace sf::historian::test {
namespace {

using namespace std::chrono_literals;

const Timestamp kT0 = from_micros(1'763'683'200'000'000);  // 2025-11-21T00:00:00Z

SeriesInfo info(std::string node, DataType type = DataType::float64) {
  return SeriesInfo{"opc.tcp://cell1:4840", std::move(node), "/Objects/Cell1/" + std::string{"x"}, type,
                    "°C"};
}

Sample sample(SeriesId id, Micros at, Value v, std::uint32_t seq = 0, StatusCode status = kGood) {
  return make_sample(id, kT0 + at, kT0 + at + 1ms, std::move(v), seq, status);
}

template <typename B>
class StoreSuite : public ::testing::Test {
 protected:
  void SetUp() override {
    SF_REQUIRE_BACKEND(B);
    backend_ = B::make();
    store_ = open();
  }

  std::unique_ptr<Store> open(const StoreOptions& options = {}) {
    auto s = open_store(backend_->url(), options);
    EXPECT_TRUE(s.ok()) << s.error().describe();
    return s ? std::move(*s) : nullptr;
  }

  SeriesId series(const std::string& node, DataType type = DataType::float64) {
    auto id = store_->register_series(info(node, type));
    EXPECT_TRUE(id.ok()) << id.error().describe();
    return id.value_or(0);
  }

  std::vector<Sample> all(SeriesId id) {
    auto rows = store_->read_raw(id, kT0 - 1000h, kT0 + 1000h, 1'000'000);
    EXPECT_TRUE(rows.ok()) << rows.error().describe();
    return rows.value_or({});
  }

  std::unique_ptr<Backend> backend_;
  std::unique_ptr<Store> store_;
};

TYPED_TEST_SUITE(StoreSuite, Backends, BackendNames);

TYPED_TEST(StoreSuite, OpensWithTheNewestSchema) {
  auto v = this->store_->schema_version();
  ASSERT_TRUE(v.ok()) << v.error().describe();
  EXPECT_EQ(*v, latest_schema_version());
  EXPECT_EQ(this->store_->backend(), TypeParam::kName);
}

TYPED_TEST(StoreSuite, RegisteringIsIdempotentAndUpdatesTheDescription) {
  auto a = this->store_->register_series(info("ns=2;s=Temp"));
  auto b = this->store_->register_series(info("ns=2;s=Temp"));
  ASSERT_TRUE(a.ok() && b.ok());
  EXPECT_EQ(*a, *b);
  EXPECT_EQ(*a, series_id("opc.tcp://cell1:4840", "ns=2;s=Temp"));
  auto changed = info("ns=2;s=Temp");
  changed.unit = "K";
  changed.browse_path = "/Objects/Cell1/Oven/Temp";
  ASSERT_EQ(this->store_->register_series(changed).value_or(0), *a);
  const auto other = this->series("ns=2;s=Pressure");
  EXPECT_NE(other, *a);
  auto list = this->store_->list_series();
  ASSERT_TRUE(list.ok());
  ASSERT_EQ(list->size(), 2U);
  const auto& temp = list->at(0).id == *a ? list->at(0) : list->at(1);
  EXPECT_EQ(temp.info, changed);
}

TYPED_TEST(StoreSuite, RegisteringWithoutAKeyIsRefused) {
  auto id = this->store_->register_series(SeriesInfo{"", "ns=1;i=5"});
  ASSERT_FALSE(id.ok());
  EXPECT_EQ(id.error().code, Errc::invalid_argument);
}

TYPED_TEST(StoreSuite, EveryValueTypeRoundTrips) {
  const auto id = this->series("ns=2;s=Any");
  const std::vector<Sample> in = {
      sample(id, 1s, Value{true}),
      sample(id, 2s, Value{false}),
      sample(id, 3s, Value{std::numeric_limits<std::int64_t>::min()}),
      sample(id, 4s, Value{std::int64_t{42}}),
      sample(id, 5s, Value{std::numeric_limits<std::uint64_t>::max()}),
      sample(id, 6s, Value{3.141592653589793}),
      sample(id, 7s, Value{-1e-300}),
      sample(id, 8s, Value{std::numeric_limits<double>::infinity()}),
      sample(id, 9s, Value{std::string{"tab\there, newline\nand back\\slash, Grüße, 温度"}}),
      sample(id, 10s, Value{std::string{}}),
      sample(id, 11s, Value{Bytes{0x00, 0x5c, 0x09, 0x0a, 0xff}}),
      sample(id, 12s, Value{Bytes{}}),
      sample(id, 13s, Value{}, 0, 0x80340000),  // BadNodeIdUnknown without a value
  };
  ASSERT_TRUE(this->store_->append(in).ok());
  EXPECT_EQ(this->all(id), in);
}

TYPED_TEST(StoreSuite, NanRoundTrips) {
  const auto id = this->series("ns=2;s=NaN");
  ASSERT_TRUE(this->store_->append(std::vector{sample(id, 1s, Value{std::nan("")})}).ok());
  const auto rows = this->all(id);
  ASSERT_EQ(rows.size(), 1U);
  ASSERT_EQ(type_of(rows[0].value), DataType::float64);
  EXPECT_TRUE(std::isnan(std::get<double>(rows[0].value)));
}

TYPED_TEST(StoreSuite, RawRangeIsHalfOpenOrderedAndLimited) {
  const auto id = this->series("ns=2;s=Ramp");
  const auto other = this->series("ns=2;s=Other");
  std::vector<Sample> in;
  for (int i = 9; i >= 0; --i) {  // written newest first
    in.push_back(sample(id, i * 1s, Value{double(i)}));
    in.push_back(sample(other, i * 1s, Value{-1.0}));
  }
  ASSERT_TRUE(this->store_->append(in).ok());
  auto rows = this->store_->read_raw(id, kT0 + 2s, kT0 + 5s, 100);
  ASSERT_TRUE(rows.ok());
  ASSERT_EQ(rows->size(), 3U);
  EXPECT_EQ(rows->at(0).value, Value{2.0});
  EXPECT_EQ(rows->at(2).value, Value{4.0});
  EXPECT_EQ(rows->at(0).series, id);
  auto limited = this->store_->read_raw(id, kT0, kT0 + 10s, 4);
  ASSERT_TRUE(limited.ok());
  ASSERT_EQ(limited->size(), 4U);
  EXPECT_EQ(limited->back().value, Value{3.0});
}

TYPED_TEST(StoreSuite, AppendingTheSameKeyAgainChangesNothing) {
  const auto id = this->series("ns=2;s=Twice");
  const std::vector<Sample> batch = {sample(id, 1s, Value{1.0}), sample(id, 2s, Value{2.0})};
  ASSERT_TRUE(this->store_->append(batch).ok());
  ASSERT_TRUE(this->store_->append(batch).ok());
  // A different value under an existing key: the first write wins.
  ASSERT_TRUE(
      this->store_->append(std::vector{sample(id, 1s, Value{99.0}), sample(id, 3s, Value{3.0})}).ok());
  const auto rows = this->all(id);
  ASSERT_EQ(rows.size(), 3U);
  EXPECT_EQ(rows[0].value, Value{1.0});
  EXPECT_EQ(rows[2].value, Value{3.0});
}

TYPED_TEST(StoreSuite, SamplesWithOneSourceTimeAreToldApartBySeq) {
  const auto id = this->series("ns=2;s=Burst");
  ASSERT_TRUE(this->store_
                  ->append(std::vector{sample(id, 1s, Value{std::int64_t{2}}, 1),
                                       sample(id, 1s, Value{std::int64_t{1}}, 0)})
                  .ok());
  const auto rows = this->all(id);
  ASSERT_EQ(rows.size(), 2U);
  EXPECT_EQ(rows[0].seq, 0U);
  EXPECT_EQ(rows[1].value, Value{std::int64_t{2}});
  auto last = this->store_->latest(id);
  ASSERT_TRUE(last.ok() && last->has_value());
  EXPECT_EQ((*last)->seq, 1U);
}

TYPED_TEST(StoreSuite, ABatchWithAnUnregisteredSeriesIsRefusedWhole) {
  const auto id = this->series("ns=2;s=Known");
  auto st = this->store_->append(std::vector{sample(id, 1s, Value{1.0}), sample(12345, 1s, Value{1.0})});
  ASSERT_FALSE(st.ok());
  EXPECT_EQ(st.error().code, Errc::not_found);
  EXPECT_NE(st.error().message.find("12345"), std::string::npos) << st.error().message;
  EXPECT_TRUE(this->all(id).empty());
}

TYPED_TEST(StoreSuite, LatestIsTheNewestSample) {
  const auto id = this->series("ns=2;s=Latest");
  auto none = this->store_->latest(id);
  ASSERT_TRUE(none.ok());
  EXPECT_FALSE(none->has_value());
  ASSERT_TRUE(this->store_
                  ->append(std::vector{sample(id, 5s, Value{5.0}), sample(id, 9s, Value{9.0}),
                                       sample(id, 7s, Value{7.0})})
                  .ok());
  auto last = this->store_->latest(id);
  ASSERT_TRUE(last.ok() && last->has_value());
  EXPECT_EQ((*last)->value, Value{9.0});
  EXPECT_EQ((*last)->source_time, kT0 + 9s);
}

TYPED_TEST(StoreSuite, AggregatesPerIntervalLeaveOutBadSamples) {
  const auto id = this->series("ns=2;s=Agg");
  std::vector<Sample> in;
  for (int i = 0; i < 10; ++i) {
    in.push_back(sample(id, i * 1s, Value{std::int64_t{i}}));
  }
  in.push_back(sample(id, 2500ms, Value{1000.0}, 0, 0x80000000));  // Bad: not counted
  in.push_back(sample(id, 12s, Value{std::uint64_t{1} << 63U}));   // past 2^63
  ASSERT_TRUE(this->store_->append(in).ok());
  auto rows = this->store_->aggregate(id, kT0, kT0 + 15s, 5s, Aggregate::all);
  ASSERT_TRUE(rows.ok()) << rows.error().describe();
  ASSERT_EQ(rows->size(), 3U);
  EXPECT_EQ(rows->at(0), (AggregateRow{kT0, 5U, 0.0, 4.0, 2.0}));
  EXPECT_EQ(rows->at(1), (AggregateRow{kT0 + 5s, 5U, 5.0, 9.0, 7.0}));
  EXPECT_EQ(rows->at(2).start, kT0 + 10s);
  EXPECT_DOUBLE_EQ(rows->at(2).max.value_or(0), 9223372036854775808.0);
  auto some = this->store_->aggregate(id, kT0, kT0 + 5s, 5s, Aggregate::avg | Aggregate::count);
  ASSERT_TRUE(some.ok());
  ASSERT_EQ(some->size(), 1U);
  EXPECT_EQ(some->at(0), (AggregateRow{kT0, 5U, std::nullopt, std::nullopt, 2.0}));
  auto bad = this->store_->aggregate(id, kT0, kT0 + 5s, 0s, Aggregate::all);
  ASSERT_FALSE(bad.ok());
  EXPECT_EQ(bad.error().code, Errc::invalid_argument);
}

TYPED_TEST(StoreSuite, EventsRoundTripFilterAndAreIdempotent) {
  const std::vector<Event> in = {
      Event{"opc.tcp://a:4840", Bytes{1, 2, 0, 3}, kT0 + 1s, kT0 + 2s, "i=2041", "ns=2;s=Oven", "Oven", 500,
            "Door opened\twhile hot", R"({"Temperature": 180.5})"},
      Event{"opc.tcp://b:4840", Bytes{9}, kT0 + 3s, kT0 + 3s, "i=2041", "ns=2;s=Robot", "Robot", 900, "Stop",
            ""},
  };
  ASSERT_TRUE(this->store_->append_events(in).ok());
  ASSERT_TRUE(this->store_->append_events(in).ok());
  auto all = this->store_->read_events(EventQuery{kT0, kT0 + 1h});
  ASSERT_TRUE(all.ok()) << all.error().describe();
  EXPECT_EQ(*all, in);
  auto only_b = this->store_->read_events(EventQuery{kT0, kT0 + 1h, "opc.tcp://b:4840"});
  ASSERT_TRUE(only_b.ok());
  ASSERT_EQ(only_b->size(), 1U);
  EXPECT_EQ(only_b->front(), in[1]);
}

TYPED_TEST(StoreSuite, RetentionDeletesWhatIsOlder) {
  const auto id = this->series("ns=2;s=Days");
  std::vector<Sample> in;
  for (int h = 0; h < 72; h += 6) {  // three days
    in.push_back(sample(id, std::chrono::hours{h}, Value{double(h)}));
  }
  ASSERT_TRUE(this->store_->append(in).ok());
  ASSERT_TRUE(
      this->store_
          ->append_events(std::vector{Event{"s", Bytes{1}, kT0 + 1h}, Event{"s", Bytes{2}, kT0 + 60h}})
          .ok());
  auto result = this->store_->apply_retention(kT0 + 36h);
  ASSERT_TRUE(result.ok()) << result.error().describe();
  const auto rows = this->all(id);
  ASSERT_EQ(rows.size(), 6U);
  EXPECT_EQ(rows.front().source_time, kT0 + 36h);
  auto events = this->store_->read_events(EventQuery{kT0 - 1h, kT0 + 100h});
  ASSERT_TRUE(events.ok());
  EXPECT_EQ(events->size(), 1U);
  if (this->store_->backend() == "postgresql") {
    // Day one went as whole partitions (samples, events); day two row by row.
    EXPECT_EQ(result->partitions_dropped, 2U);
    EXPECT_EQ(result->samples_deleted, 2U);
  } else {
    EXPECT_EQ(result->samples_deleted, 6U);
    EXPECT_EQ(result->events_deleted, 1U);
  }
  // Old data arriving late still has somewhere to go.
  ASSERT_TRUE(this->store_->append(std::vector{sample(id, 1h, Value{-1.0})}).ok());
  EXPECT_EQ(this->all(id).size(), 7U);
}

TYPED_TEST(StoreSuite, ABigBatchArrivesWhole) {
  const auto id = this->series("ns=2;s=Big");
  std::vector<Sample> in;
  for (int i = 0; i < 20'000; ++i) {
    in.push_back(sample(id, i * 1ms, Value{double(i) * 0.5}));
  }
  ASSERT_TRUE(this->store_->append(in).ok());
  EXPECT_EQ(this->all(id), in);
}

TYPED_TEST(StoreSuite, DataSurvivesReopening) {
  const auto id = this->series("ns=2;s=Kept");
  ASSERT_TRUE(this->store_->append(std::vector{sample(id, 1s, Value{std::string{"kept"}})}).ok());
  this->store_.reset();
  this->store_ = this->open();
  ASSERT_NE(this->store_, nullptr);
  EXPECT_EQ(this->all(id).size(), 1U);
  EXPECT_EQ(this->store_->list_series().value_or({}).size(), 1U);
}

TYPED_TEST(StoreSuite, MigratesAnOlderSchemaOnOpen) {
  // A database made by a build that knew only version 1.
  auto fresh = TypeParam::make();
  auto old = open_store(fresh->url(), StoreOptions{.schema_target = 1});
  ASSERT_TRUE(old.ok()) << old.error().describe();
  EXPECT_EQ((*old)->schema_version().value_or(0), 1);
  old->reset();
  auto now = open_store(fresh->url());
  ASSERT_TRUE(now.ok()) << now.error().describe();
  EXPECT_EQ((*now)->schema_version().value_or(0), latest_schema_version());
  auto migrations = fresh->sql("SELECT version FROM schema_migrations ORDER BY version");
  ASSERT_TRUE(migrations.ok());
  EXPECT_EQ(*migrations, "1\n2\n");
}

TYPED_TEST(StoreSuite, ANewerSchemaIsRefused) {
  ASSERT_TRUE(this->backend_->sql("INSERT INTO schema_migrations VALUES (99, 'from the future', 0)").ok());
  this->store_.reset();
  auto s = open_store(this->backend_->url());
  ASSERT_FALSE(s.ok());
  EXPECT_EQ(s.error().code, Errc::unsupported);
  EXPECT_NE(s.error().message.find("newer"), std::string::npos) << s.error().message;
}

}  // namespace
}  // namespace sf::historian::test
