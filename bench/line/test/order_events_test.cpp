// The line benchmark's reading of the order service's events (`smartfactory orders --json` lines
// in the line's log/orders.log) into each order's times, and the orders it feeds the line.
#include <gtest/gtest.h>

#include <fstream>
#include <set>

#include "sf/bench/line.hpp"
#include "sf/testing/temp_dir.hpp"

namespace sf::bench {
namespace {

LoggedOrderEvent event(double t, std::string order, std::string what) {
  return {t, std::move(order), std::move(what), "", ""};
}

// Lines as the line's log/orders.log holds them: the supervisor's header, the service's ready line,
// its order events and a log line on stderr.
TEST(OrderEventLines, OnlyTheOrderEventsAreRead) {
  const auto e = parse_order_event(
      R"j({"detail":"upload (round 1)","event":"order","machine":"uploader","order":"o-1","t":0.028102,"what":"awarded"})j");
  ASSERT_TRUE(e.has_value());
  EXPECT_DOUBLE_EQ(e->t, 0.028102);
  EXPECT_EQ(e->order, "o-1");
  EXPECT_EQ(e->what, "awarded");
  EXPECT_EQ(e->machine, "uploader");
  EXPECT_EQ(e->detail, "upload (round 1)");
  for (const char* other : {
           "--- line: starting smartfactory orders --config run/config/orders.yaml --json ---",
           R"({"conveying_domain":11,"event":"ready","machine":"order-service","orders":30})",
           R"({"done":3,"event":"status","failed":0,"in_work":3,"queued":24,"remade":0})",
           "2026-11-27 13:57:01.123 W negotiation: late bid",
           R"({"detail":"","event":"order","machine":"","order":"o-1","t":1.5,"wh)",  // cut off
           R"({"event":"order","order":"o-1","t":"soon","what":"done"})",
       }) {
    EXPECT_FALSE(parse_order_event(other).has_value()) << other;
  }
}

TEST(OrderTimes, FirstAwardAndDoneOfEachOrderInAcceptanceOrder) {
  const std::vector<LoggedOrderEvent> events{
      event(0.0, "a", "accepted"),    event(0.0, "b", "accepted"), event(0.02, "a", "awarded"),
      event(1.5, "a", "uploaded"),    event(1.51, "a", "awarded"),  // a's second award is not its first
      event(5.0, "a", "transported"), event(5.03, "b", "awarded"), event(28.0, "a", "done"),
      event(40.0, "b", "done")};
  const auto times = order_times(events);
  ASSERT_EQ(times.size(), 2U);
  EXPECT_EQ(times[0].order, "a");
  EXPECT_DOUBLE_EQ(*times[0].first_award, 0.02);
  EXPECT_DOUBLE_EQ(*times[0].done, 28.0);
  EXPECT_FALSE(times[0].failed);
  EXPECT_EQ(times[1].order, "b");
  EXPECT_DOUBLE_EQ(*times[1].first_award, 5.03);
  EXPECT_DOUBLE_EQ(*times[1].done, 40.0);
}

// What let an order start: the latest event of another order before its first award (here a's box
// leaving the uploader's belt, then a's done freeing a place), or its own acceptance when that came
// later (one order at a time).
TEST(OrderTimes, TheWaitBeforeTheFirstAwardEndsAtTheLatestEventOfAnotherOrder) {
  const std::vector<LoggedOrderEvent> events{
      event(0.0, "a", "accepted"),  event(0.0, "b", "accepted"),    event(0.0, "c", "accepted"),
      event(0.02, "a", "awarded"),  event(5.0, "a", "transported"), event(5.02, "b", "awarded"),
      event(28.0, "a", "done"),     event(28.01, "b", "loaded"),    event(28.0, "c", "retry"),
      event(28.03, "c", "awarded"), event(40.0, "b", "done"),       event(41.0, "c", "done"),
      event(50.0, "d", "accepted"), event(50.02, "d", "awarded")};
  const auto times = order_times(events);
  ASSERT_EQ(times.size(), 4U);
  EXPECT_EQ(times[0].started_by, "accepted");
  EXPECT_DOUBLE_EQ(times[0].started_at, 0.0);
  EXPECT_EQ(times[1].started_by, "transported");
  EXPECT_DOUBLE_EQ(times[1].started_at, 5.0);
  EXPECT_EQ(times[2].started_by, "loaded");  // c's own retry does not count
  EXPECT_DOUBLE_EQ(times[2].started_at, 28.01);
  EXPECT_EQ(times[3].started_by, "accepted");  // c's done came before d was accepted
  EXPECT_DOUBLE_EQ(times[3].started_at, 50.0);
}

// A failed attempt that is remade is not the order's end; a failure without a remake is.
TEST(OrderTimes, AnOrderRemadeEndsWithItsLastAttempt) {
  const std::vector<LoggedOrderEvent> events{
      event(0.0, "a", "accepted"),  event(0.1, "a", "awarded"),  event(30.0, "a", "failed"),
      event(30.0, "a", "remade"),   event(30.1, "a", "awarded"), event(60.0, "a", "done"),
      event(61.0, "b", "accepted"), event(90.0, "b", "failed"),  event(90.0, "z", "done")};  // z unknown
  const auto times = order_times(events);
  ASSERT_EQ(times.size(), 2U);
  EXPECT_DOUBLE_EQ(*times[0].first_award, 0.1);
  EXPECT_DOUBLE_EQ(*times[0].done, 60.0);
  EXPECT_FALSE(times[0].failed);
  EXPECT_FALSE(times[1].first_award.has_value());
  EXPECT_TRUE(times[1].failed);
}

TEST(Summary, PercentilesOfTheAwardsLeadTimesOfDoneOrdersAndTheSpan) {
  std::vector<LoggedOrderEvent> events;
  for (int i = 0; i < 4; ++i) {
    const std::string id = std::to_string(i);
    events.push_back(event(i, id, "accepted"));
    events.push_back(event(i + 0.01 * (i + 1), id, "awarded"));
    events.push_back(event(i + 10.0 * (i + 1), id, i == 3 ? "failed" : "done"));
  }
  const auto r = summarize(order_times(events));
  EXPECT_EQ(r.done, 3U);
  EXPECT_EQ(r.failed, 1U);
  EXPECT_DOUBLE_EQ(r.span_s, 43.0);  // accepted at 0, the last (failed) at 3 + 40
  EXPECT_EQ(r.first_award_ms.samples, 4U);
  EXPECT_NEAR(r.first_award_ms.p50, 20.0, 1e-9);  // 10, 20, 30, 40 ms: nearest rank
  EXPECT_NEAR(r.first_award_ms.p99, 40.0, 1e-9);
  EXPECT_EQ(r.lead_time_s.samples, 3U);
  EXPECT_NEAR(r.lead_time_s.p50, 20.0, 1e-9);
  EXPECT_NEAR(r.lead_time_s.p99, 30.0, 1e-9);
}

TEST(SmallOrders, TheSmallestBoxWithOneCandyOfOneOrTwoTypesSameForTheSameSeed) {
  const auto layout = line::default_layout();
  ASSERT_TRUE(layout);
  const auto orders = small_orders(layout->catalog, 40, 7, "x");
  ASSERT_EQ(orders.size(), 40U);
  EXPECT_EQ(orders, small_orders(layout->catalog, 40, 7, "x"));
  EXPECT_NE(orders, small_orders(layout->catalog, 40, 8, "x"));
  std::set<std::size_t> sizes;
  for (const auto& o : orders) {
    EXPECT_TRUE(factory::validate(o, layout->catalog)) << o.id;
    EXPECT_EQ(o.box_type, "small-box");
    sizes.insert(o.lines.size());
    EXPECT_EQ(o.total(), static_cast<int>(o.lines.size()));
    EXPECT_EQ(o.counts().size(), o.lines.size());  // distinct types
  }
  EXPECT_EQ(sizes, (std::set<std::size_t>{1, 2}));
  EXPECT_EQ(orders.front().id, "x-1");
}

// Another process appends to the file; a line is returned once it is complete, and only once.
TEST(FileLines, CompleteLinesAsTheyAreAppended) {
  sf::testing::TempDir dir;
  const auto path = dir.path() / "log";
  FileLines lines(path);
  EXPECT_TRUE(lines.read_new().empty());  // no file yet
  std::ofstream out(path);
  out << "one\ntw" << std::flush;
  EXPECT_EQ(lines.read_new(), std::vector<std::string>{"one"});
  out << "o\nthree\n" << std::flush;
  EXPECT_EQ(lines.read_new(), (std::vector<std::string>{"two", "three"}));
  EXPECT_TRUE(lines.read_new().empty());
}

}  // namespace
}  // namespace sf::bench
