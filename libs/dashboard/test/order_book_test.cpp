// The order book from order-step events as the order service raises them (OrderModel::raise):
// the order's state, and where its box is for the operator's schematic.
#include "sf/dashboard/order_book.hpp"

#include <gtest/gtest.h>

#include <string>

namespace sf::dashboard {
namespace {

class OrderBookTest : public ::testing::Test {
 protected:
  // One step of order `id` at second `t` (format_order_step's text as the event's Message).
  void step(const std::string& id, int t, const std::string& what, const std::string& machine,
            const std::string& detail) {
    historian::Event e;
    e.server = "orders";
    e.source_node = "ns=2;s=OrderService";
    e.source_name = id;
    e.time = historian::Timestamp{std::chrono::seconds{1'800'000'000 + t}};
    e.message = line::format_order_step({what, machine, detail});
    ASSERT_EQ(book.on_event(e), id);
  }
  BoxPlace place(const std::string& id) {
    auto o = book.find(id);
    EXPECT_TRUE(o && o->place) << id << " has no place";
    return o && o->place ? *o->place : BoxPlace{};
  }

  OrderBook book;
};

TEST_F(OrderBookTest, TheBoxIsWhereItWasPutThenOnItsRouteUntilItIsDone) {
  step("o-1", 1, "accepted", "", "small-box gummy:2");
  step("o-1", 2, "started", "", "attempt 1");
  EXPECT_FALSE(book.find("o-1")->place) << "no box before the uploader put one";
  step("o-1", 3, "awarded", "uploader", "upload (round 1; bids: uploader cost 1.00 queue 0)");
  step("o-1", 4, "uploaded", "uploader", "box 12 at conveyor1/upload");
  EXPECT_EQ(place("o-1").box, 12);
  EXPECT_EQ(place("o-1").at, "conveyor1/upload");
  EXPECT_TRUE(place("o-1").route.empty());

  step("o-1", 5, "awarded", "denso", "load (round 1; bids: denso cost 2.00 queue 0)");
  step("o-1", 6, "routed", "denso",
       "conveyor1/upload -conveyor1-> conveyor1/out -conveyor3-> conveyor3/denso (4.250 s)");
  EXPECT_EQ(place("o-1").at, "conveyor1/upload");
  EXPECT_EQ(place("o-1").route,
            (std::vector<RouteLeg>{{"conveyor1", "conveyor1/out"}, {"conveyor3", "conveyor3/denso"}}));

  step("o-1", 7, "transported", "conveyor1", "box 12 conveyor1/upload → conveyor1/out");
  EXPECT_EQ(place("o-1").at, "conveyor1/out");
  EXPECT_EQ(place("o-1").route, (std::vector<RouteLeg>{{"conveyor3", "conveyor3/denso"}}));
  step("o-1", 8, "transported", "conveyor3", "box 12 conveyor1/out → conveyor3/denso");
  EXPECT_EQ(place("o-1").at, "conveyor3/denso");
  EXPECT_TRUE(place("o-1").route.empty());

  step("o-1", 9, "done", "downloader", "");
  EXPECT_EQ(book.find("o-1")->state, "done");
  EXPECT_FALSE(book.find("o-1")->place) << "a finished order's box is off the line";
}

TEST_F(OrderBookTest, ARetryDropsTheRouteAndANewAttemptStartsWithoutABox) {
  step("o-2", 1, "started", "", "attempt 1");
  step("o-2", 2, "uploaded", "uploader", "box 3 at conveyor1/upload");
  step("o-2", 3, "routed", "toshiba", "conveyor1/upload -conveyor3-> conveyor3/toshiba (2.000 s)");
  step("o-2", 4, "retry", "toshiba", "transport conveyor1/upload → conveyor3/toshiba on conveyor3: jammed");
  EXPECT_EQ(place("o-2").at, "conveyor1/upload") << "it stays where it stood";
  EXPECT_TRUE(place("o-2").route.empty());

  step("o-2", 5, "remade", "", "attempt 2");
  EXPECT_FALSE(book.find("o-2")->place);
  step("o-2", 6, "started", "", "attempt 2");
  step("o-2", 7, "uploaded", "uploader", "box 4 at conveyor1/upload");
  EXPECT_EQ(place("o-2").box, 4);
}

TEST_F(OrderBookTest, StepsArrivingOutOfOrderOrTwiceLeaveTheSamePlace) {
  step("o-3", 3, "transported", "conveyor3", "box 7 conveyor1/upload → conveyor3/denso");
  step("o-3", 1, "started", "", "attempt 1");
  step("o-3", 2, "uploaded", "uploader", "box 7 at conveyor1/upload");
  EXPECT_EQ(place("o-3").at, "conveyor3/denso");
  historian::Event again;
  again.server = "orders";
  again.source_node = "ns=2;s=OrderService";
  again.source_name = "o-3";
  again.time = historian::Timestamp{std::chrono::seconds{1'800'000'002}};
  again.message = line::format_order_step({"uploaded", "uploader", "box 7 at conveyor1/upload"});
  EXPECT_FALSE(book.on_event(again)) << "a step seen before changes nothing";
  EXPECT_EQ(place("o-3").at, "conveyor3/denso");
}

TEST_F(OrderBookTest, DetailsThatDoNotReadAsPlacesLeaveThePlaceAlone) {
  step("o-4", 1, "started", "", "attempt 1");
  step("o-4", 2, "uploaded", "uploader", "box twelve at conveyor1/upload");
  EXPECT_FALSE(book.find("o-4")->place);
  step("o-4", 3, "uploaded", "uploader", "box 5 at conveyor1/upload");
  step("o-4", 4, "routed", "denso", "conveyor1/upload conveyor3 conveyor3/denso");
  step("o-4", 5, "routed", "denso", "conveyor1/upload -> conveyor3/denso (1.000 s)");
  EXPECT_TRUE(place("o-4").route.empty());
  step("o-4", 6, "transported", "conveyor3", "box");
  EXPECT_EQ(place("o-4").at, "conveyor1/upload");
  EXPECT_EQ(book.rejected(), 0U) << "steps that parse are not rejected for their detail";
}

}  // namespace
}  // namespace sf::dashboard
