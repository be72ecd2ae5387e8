// BufferedStore over a real SQLite store behind a switch that takes it
// "down"; time is a ManualClock, so back-off is exact and instant.
#include <gtest/gtest.h>

#include "hooked_store.hpp"
#include "make_sample.hpp"
#include "sf/historian/buffered_store.hpp"
#include "temp_dir.hpp"

namespace sf::historian {
namespace {

using namespace std::chrono_literals;
using test::HookedStore;

const Timestamp kT0 = from_micros(1'763'683'200'000'000);

class BufferedStoreTest : public ::testing::Test {
 protected:
  void SetUp() override { reopen(); }

  void reopen(BufferOptions options = {}) {
    store_.reset();
    options.directory = dir_.path() / "buffer";
    auto s = BufferedStore::open(
        [this]() -> Result<std::unique_ptr<Store>> {
          ++opens_;
          auto db = open_store("sqlite:" + (dir_.path() / db_name_).string());
          if (!db) {
            return db.error();
          }
          return std::unique_ptr<Store>{std::make_unique<HookedStore>(
              std::move(*db), [this](std::string_view op) -> std::optional<Error> {
                ++calls_;
                return up_ || op == "read" ? std::nullopt : std::optional{test::unreachable()};
              })};
        },
        options, clock_);
    ASSERT_TRUE(s.ok()) << s.error().describe();
    store_ = std::move(*s);
  }

  SeriesId series(const std::string& node) {
    auto id = store_->register_series(SeriesInfo{"opc.tcp://m1:4840", node});
    EXPECT_TRUE(id.ok()) << id.error().describe();
    return id.value_or(0);
  }

  static std::vector<Sample> batch(SeriesId id, int n) {
    std::vector<Sample> out;
    for (int i = 0; i < 3; ++i) {
      out.push_back(test::make_sample(id, kT0 + (n * 3 + i) * 1ms, kT0, Value{std::int64_t{n * 3 + i}}));
    }
    return out;
  }

  std::vector<Sample> stored(SeriesId id) {
    auto db = open_store("sqlite:" + (dir_.path() / db_name_).string());
    EXPECT_TRUE(db.ok());
    return (*db)->read_raw(id, kT0 - 1h, kT0 + 1h, 100'000).value_or({});
  }

  test::TempDir dir_;
  std::string db_name_ = "history.db";
  ManualClock clock_;
  bool up_ = true;
  int calls_ = 0;
  int opens_ = 0;
  std::unique_ptr<BufferedStore> store_;
};

TEST_F(BufferedStoreTest, WhileTheDatabaseAnswersNothingIsBuffered) {
  const auto id = series("ns=2;s=A");
  ASSERT_TRUE(store_->append(batch(id, 0)).ok());
  EXPECT_EQ(store_->stats().samples_buffered, 0U);
  EXPECT_TRUE(store_->stats().database_up);
  EXPECT_EQ(stored(id), batch(id, 0));
  auto read = store_->read_raw(id, kT0, kT0 + 1s, 10);
  ASSERT_TRUE(read.ok());
  EXPECT_EQ(read->size(), 3U);
}

TEST_F(BufferedStoreTest, AnOutageIsBufferedAndForwardedInOrder) {
  const auto id = series("ns=2;s=A");
  ASSERT_TRUE(store_->append(batch(id, 0)).ok());
  up_ = false;
  for (int n = 1; n < 6; ++n) {
    ASSERT_TRUE(store_->append(batch(id, n)).ok());
  }
  auto stats = store_->stats();
  EXPECT_FALSE(stats.database_up);
  EXPECT_EQ(stats.buffered_records, 5U);
  EXPECT_EQ(stats.samples_buffered, 15U);
  EXPECT_NE(stats.last_error.find("unreachable"), std::string::npos);
  up_ = true;
  // Later writes queue behind the buffered ones, even with the database back.
  ASSERT_TRUE(store_->append(batch(id, 6)).ok());
  EXPECT_EQ(store_->stats().buffered_records, 6U);
  clock_.advance(1s);
  ASSERT_TRUE(store_->poll().ok());
  EXPECT_EQ(store_->stats().buffered_records, 0U);
  std::vector<Sample> expected;
  for (int n = 0; n < 7; ++n) {
    const auto b = batch(id, n);
    expected.insert(expected.end(), b.begin(), b.end());
  }
  EXPECT_EQ(stored(id), expected);
  ASSERT_TRUE(store_->append(batch(id, 7)).ok());
  EXPECT_EQ(store_->stats().buffered_records, 0U) << "straight through again";
}

TEST_F(BufferedStoreTest, EventsAreBufferedAndForwardedToo) {
  const Event e{.server = "opc.tcp://m1:4840", .event_id = Bytes{7}, .time = kT0, .message = "door open"};
  up_ = false;
  ASSERT_TRUE(store_->append_events(std::vector{e}).ok());
  EXPECT_EQ(store_->stats().buffered_records, 1U);
  up_ = true;
  ASSERT_TRUE(store_->flush().ok());
  auto db = open_store("sqlite:" + (dir_.path() / db_name_).string());
  ASSERT_TRUE(db.ok());
  EXPECT_EQ((*db)->read_events(EventQuery{.from = kT0, .to = kT0 + 1s}).value_or({}), std::vector{e});
}

TEST_F(BufferedStoreTest, RetriesBackOffExponentially) {
  const auto id = series("ns=2;s=A");
  up_ = false;
  ASSERT_TRUE(store_->append(batch(id, 0)).ok());  // fails: back off 200 ms
  const int after_first = calls_;
  EXPECT_FALSE(store_->poll().ok());
  EXPECT_EQ(calls_, after_first) << "no attempt before the back-off ends";
  std::vector<int> attempts_at_ms;
  for (int ms = 0; ms < 3000; ms += 10) {
    clock_.advance(10ms);
    const int before = calls_;
    (void)store_->poll();
    if (calls_ != before) {
      attempts_at_ms.push_back(ms + 10);
    }
  }
  EXPECT_EQ(attempts_at_ms, (std::vector<int>{200, 600, 1400, 3000}));
}

TEST_F(BufferedStoreTest, ACallersMistakeIsReportedNotBuffered) {
  auto st = store_->append(batch(999, 0));
  ASSERT_FALSE(st.ok());
  EXPECT_EQ(st.error().code, Errc::not_found);
  EXPECT_EQ(store_->stats().buffered_records, 0U);
  EXPECT_EQ(store_->register_series(SeriesInfo{}).error().code, Errc::invalid_argument);
}

TEST_F(BufferedStoreTest, ARefusedRecordIsSetAsideAndTheRestFlows) {
  const auto id = series("ns=2;s=A");
  up_ = false;
  ASSERT_TRUE(store_->append(batch(id, 0)).ok());
  ASSERT_TRUE(store_->append(batch(424242, 1)).ok());  // never registered anywhere
  ASSERT_TRUE(store_->append(batch(id, 2)).ok());
  up_ = true;
  ASSERT_TRUE(store_->flush().ok());
  EXPECT_EQ(store_->stats().records_rejected, 1U);
  EXPECT_EQ(store_->stats().buffered_records, 0U);
  auto expected = batch(id, 0);
  const auto more = batch(id, 2);
  expected.insert(expected.end(), more.begin(), more.end());
  EXPECT_EQ(stored(id), expected);
  EXPECT_TRUE(std::filesystem::exists(dir_.path() / "buffer" / "rejected.log"));
}

TEST_F(BufferedStoreTest, AFullBufferRefusesMore) {
  reopen(BufferOptions{.max_buffered_bytes = 200});  // one batch of 3 samples is 128 bytes
  const auto id = series("ns=2;s=A");
  up_ = false;
  ASSERT_TRUE(store_->append(batch(id, 0)).ok());
  auto st = store_->append(batch(id, 1));
  ASSERT_FALSE(st.ok());
  EXPECT_EQ(st.error().code, Errc::limit_exceeded);
  EXPECT_NE(st.error().message.find("full"), std::string::npos);
}

TEST_F(BufferedStoreTest, ReadsWhileTheDatabaseIsAwaySayWhy) {
  const auto id = series("ns=2;s=A");
  up_ = false;
  ASSERT_TRUE(store_->append(batch(id, 0)).ok());
  auto read = store_->latest(id);
  ASSERT_FALSE(read.ok());
  EXPECT_EQ(read.error().code, Errc::io);
  EXPECT_NE(read.error().message.find("1 records buffered"), std::string::npos) << read.error().message;
}

TEST_F(BufferedStoreTest, SeriesAreRegisteredAgainInADatabaseThatLostThem) {
  const auto id = series("ns=2;s=A");
  up_ = false;
  ASSERT_TRUE(store_->append(batch(id, 0)).ok());
  // The database comes back from an old backup: a fresh file without the series.
  db_name_ = "restored.db";
  up_ = true;
  clock_.advance(1s);
  ASSERT_TRUE(store_->flush().ok());
  EXPECT_EQ(store_->stats().records_rejected, 0U);
  EXPECT_EQ(stored(id), batch(id, 0));
}

TEST_F(BufferedStoreTest, OpensWhileTheDatabaseIsAwayAndBuffersRegistrations) {
  db_name_ = "no-such-dir/history.db";
  reopen();
  const auto id = series("ns=2;s=Offline");
  EXPECT_EQ(id, series_id("opc.tcp://m1:4840", "ns=2;s=Offline"));
  ASSERT_TRUE(store_->append(batch(id, 0)).ok());
  EXPECT_EQ(store_->stats().buffered_records, 2U);
  std::filesystem::create_directories(dir_.path() / "no-such-dir");
  clock_.advance(1s);
  ASSERT_TRUE(store_->poll().ok());
  EXPECT_EQ(stored(id), batch(id, 0));
}

}  // namespace
}  // namespace sf::historian
