// Faults, against both back ends: the database goes away in the middle of a
// stream of writes (PostgreSQL: the server is killed while a writer thread
// appends, then restarted; SQLite: another connection holds the write lock),
// and acknowledgements get lost after commits. Afterwards every sample is
// there exactly once, in order — checked by count and by content.
#include <atomic>
#include <thread>

#include <gtest/gtest.h>

#include "hooked_store.hpp"
#include "make_sample.hpp"
#include "sf/historian/buffered_store.hpp"
#include "store_backends.hpp"

namespace sf::historian::test {
namespace {

using namespace std::chrono_literals;

const Timestamp kFaultT0 = from_micros(1'763'683'200'000'000);

std::vector<Sample> batch(SeriesId id, int n, int per_batch) {
  std::vector<Sample> out;
  for (int i = 0; i < per_batch; ++i) {
    const auto k = n * per_batch + i;
    out.push_back(make_sample(id, kFaultT0 + k * 1ms, kFaultT0 + k * 1ms + 5us, Value{double(k) / 4}));
  }
  return out;
}

template <typename B>
class StoreFaults : public ::testing::Test {
 protected:
  void SetUp() override {
    SF_REQUIRE_BACKEND(B);
    backend_ = B::make();
  }

  void expect_exactly(const std::vector<Sample>& expected, SeriesId id) {
    auto store = open_store(backend_->url());
    ASSERT_TRUE(store.ok()) << store.error().describe();
    auto rows = (*store)->read_raw(id, kFaultT0 - 1h, kFaultT0 + 100h, 10 * expected.size() + 10);
    ASSERT_TRUE(rows.ok()) << rows.error().describe();
    ASSERT_EQ(rows->size(), expected.size()) << "samples missing or duplicated";
    EXPECT_TRUE(*rows == expected) << "samples differ in content or order";
  }

  std::unique_ptr<Backend> backend_;
  TempDir buffer_dir_;
  ManualClock clock_;
};

TYPED_TEST_SUITE(StoreFaults, Backends, BackendNames);

TYPED_TEST(StoreFaults, DatabaseGoneMidStreamLosesAndDuplicatesNothing) {
  auto store =
      BufferedStore::open(this->backend_->url(), BufferOptions{this->buffer_dir_.path()}, this->clock_);
  ASSERT_TRUE(store.ok()) << store.error().describe();
  auto id = (*store)->register_series(SeriesInfo{"opc.tcp://line:4840", "ns=2;s=Speed"});
  ASSERT_TRUE(id.ok()) << id.error().describe();

  constexpr int kBatches = 120;
  constexpr int kPerBatch = 50;
  std::atomic<int> written{0};
  std::atomic<bool> down{false};
  // The database goes away from another thread while the writer is busy,
  // after batch 30; the writer comes to batch 60 only once that happened, and
  // brings it back after batch 80 (from this thread: a restarted server is a
  // child of the thread that starts it, and dies with it).
  std::thread fault([&] {
    while (written.load() < 30) {
      std::this_thread::yield();
    }
    this->backend_->make_unavailable();
    down = true;
  });
  std::vector<Sample> expected;
  for (int n = 0; n < kBatches; ++n) {
    while (n == 60 && !down.load()) {
      std::this_thread::yield();
    }
    if (n == 80) {
      this->backend_->make_available();
    }
    const auto b = batch(*id, n, kPerBatch);
    auto st = (*store)->append(b);
    ASSERT_TRUE(st.ok()) << st.error().describe();
    expected.insert(expected.end(), b.begin(), b.end());
    ++written;
    this->clock_.advance(100ms);
    (void)(*store)->poll();  // fails while the database is away; that is the point
  }
  fault.join();
  this->clock_.advance(1min);
  auto flushed = (*store)->flush();
  ASSERT_TRUE(flushed.ok()) << flushed.error().describe();
  const auto stats = (*store)->stats();
  EXPECT_GT(stats.samples_buffered, 0U) << "the fault should have sent samples through the buffer";
  EXPECT_EQ(stats.samples_forwarded, stats.samples_buffered);
  EXPECT_EQ(stats.buffered_records, 0U);
  EXPECT_EQ(stats.records_rejected, 0U);
  this->expect_exactly(expected, *id);
}

TYPED_TEST(StoreFaults, DatabaseAwayFromTheStartIsCaughtUpLater) {
  this->backend_->make_unavailable();
  auto store =
      BufferedStore::open(this->backend_->url(), BufferOptions{this->buffer_dir_.path()}, this->clock_);
  ASSERT_TRUE(store.ok()) << store.error().describe();
  // Registration works offline: the id is derived from the key.
  auto id = (*store)->register_series(SeriesInfo{"opc.tcp://line:4840", "ns=2;s=Offline"});
  ASSERT_TRUE(id.ok()) << id.error().describe();
  std::vector<Sample> expected;
  for (int n = 0; n < 10; ++n) {
    const auto b = batch(*id, n, 20);
    ASSERT_TRUE((*store)->append(b).ok());
    expected.insert(expected.end(), b.begin(), b.end());
  }
  EXPECT_FALSE((*store)->read_raw(*id, kFaultT0, kFaultT0 + 1h, 10).ok()) << "reads report the database away";
  this->backend_->make_available();
  this->clock_.advance(1min);
  ASSERT_TRUE((*store)->flush().ok());
  this->expect_exactly(expected, *id);
}

TYPED_TEST(StoreFaults, LostAcknowledgementsDoNotDuplicate) {
  auto url = this->backend_->url();
  int opened = 0;
  auto store = BufferedStore::open(
      [&]() -> Result<std::unique_ptr<Store>> {
        auto s = open_store(url);
        if (!s) {
          return s.error();
        }
        // The first connection loses three acknowledgements: it commits, then
        // reports a lost connection, as a writer sees a link drop during COMMIT.
        auto lose = std::make_shared<int>(opened++ == 0 ? 3 : 0);
        return std::unique_ptr<Store>{std::make_unique<HookedStore>(
            std::move(*s), nullptr, [lose](std::string_view op) -> std::optional<Error> {
              if (op != "append" || *lose == 0) {
                return std::nullopt;
              }
              --*lose;
              return make_error(Errc::io, "connection lost during commit, outcome unknown");
            })};
      },
      BufferOptions{this->buffer_dir_.path()}, this->clock_);
  ASSERT_TRUE(store.ok());
  auto id = (*store)->register_series(SeriesInfo{"opc.tcp://line:4840", "ns=2;s=Acks"});
  ASSERT_TRUE(id.ok());
  std::vector<Sample> expected;
  for (int n = 0; n < 20; ++n) {
    const auto b = batch(*id, n, 10);
    ASSERT_TRUE((*store)->append(b).ok());
    expected.insert(expected.end(), b.begin(), b.end());
    this->clock_.advance(1s);
    (void)(*store)->poll();
  }
  ASSERT_TRUE((*store)->flush().ok());
  EXPECT_GT((*store)->stats().samples_buffered, 0U);
  this->expect_exactly(expected, *id);
}

}  // namespace
}  // namespace sf::historian::test
