// Conveyor route negotiation: shortest route by ETA, the planner's REQUEST /
// INFORM rules and the conveyor role.
#include "sf/negotiation/route.hpp"

#include <gtest/gtest.h>

#include "test_support.hpp"

namespace sf::negotiation {
namespace {

using namespace std::chrono_literals;

std::vector<Segment> line() {
  // Input → M1 → M2 → M3, plus a slow direct belt M1 → M3 and a fast detour M1 → X → M3.
  return {{"C1", "Input", "M1", 1s}, {"C2", "M1", "M2", 2s}, {"C3", "M2", "M3", 2s},
          {"C4", "M1", "M3", 5s},    {"C5", "M1", "X", 1s},  {"C6", "X", "M3", 1500ms}};
}

std::vector<std::string> conveyors(const Route& r) {
  std::vector<std::string> out;
  for (const auto& s : r.segments) {
    out.push_back(s.conveyor);
  }
  return out;
}

TEST(ShortestRoute, PicksTheSmallestTotalTransitTime) {
  auto r = shortest_route(line(), "Input", "M3");
  ASSERT_TRUE(r.has_value());
  EXPECT_EQ(conveyors(*r), (std::vector<std::string>{"C1", "C5", "C6"}));
  EXPECT_EQ(r->eta(), 3500ms);
  EXPECT_EQ(r->describe(), "Input -C1-> M1 -C5-> X -C6-> M3 (3.500 s)");
}

TEST(ShortestRoute, SegmentsConnectEndToEnd) {
  auto r = shortest_route(line(), "Input", "M2");
  ASSERT_TRUE(r.has_value());
  std::string at = "Input";
  for (const auto& s : r->segments) {
    EXPECT_EQ(s.from, at);
    at = s.to;
  }
  EXPECT_EQ(at, "M2");
}

TEST(ShortestRoute, UnreachableOrBackwardsHasNoRoute) {
  EXPECT_FALSE(shortest_route(line(), "M3", "Input").has_value());
  EXPECT_FALSE(shortest_route(line(), "Input", "Nowhere").has_value());
  EXPECT_FALSE(shortest_route({}, "A", "B").has_value());
  auto same = shortest_route({}, "M1", "M1");
  ASSERT_TRUE(same.has_value());
  EXPECT_TRUE(same->segments.empty());
}

TEST(ShortestRoute, TiesGoToFewerSegments) {
  std::vector<Segment> s{{"A1", "A", "B", 1s}, {"A2", "B", "C", 1s}, {"A3", "A", "C", 2s}};
  auto r = shortest_route(s, "A", "C");
  ASSERT_TRUE(r.has_value());
  EXPECT_EQ(conveyors(*r), std::vector<std::string>{"A3"});
}

class PlannerTest : public ::testing::Test {
 protected:
  RoutePlanner make() {
    RouteConfig c;
    c.collect_window = 100ms;
    c.retry_delay = 50ms;
    c.max_attempts = 2;
    c.incarnation = 0xf;
    return RoutePlanner{transport, clock, c};
  }
  TransportInform inform(const std::string& conv, const Segment& s, std::uint16_t hops = 1) {
    return {conv, s.conveyor, s.from, s.to, s.transit_time, clock.utc_now() + s.transit_time, hops};
  }

  ManualClock clock;
  test::RecordingManagerTransport transport;
  std::vector<Result<Route>> results;
  RouteCallback record = [this](const Result<Route>& r) { results.push_back(r); };
};

TEST_F(PlannerTest, ComposesTheRouteOnceEveryConveyorInformed) {
  auto p = make();
  transport.conveyor_count = 6;
  auto id = p.plan("P1", "Input", "M3", record);
  ASSERT_TRUE(id.ok());
  ASSERT_EQ(transport.requests.size(), 1U);
  EXPECT_EQ(transport.requests[0].from, "Input");
  EXPECT_EQ(transport.requests[0].to, "M3");
  for (const auto& s : line()) {
    EXPECT_TRUE(results.empty());
    p.on_inform(inform(*id, s));
  }
  ASSERT_EQ(results.size(), 1U);
  ASSERT_TRUE(results[0].ok());
  EXPECT_EQ(conveyors(*results[0]), (std::vector<std::string>{"C1", "C5", "C6"}));
  EXPECT_EQ(transport.closed_requests, std::vector<std::string>{*id});
  EXPECT_EQ(p.active(), 0U);
}

TEST_F(PlannerTest, ComposesAtTheDeadlineWithWhatArrived) {
  auto p = make();
  transport.conveyor_count = 10;
  auto id = p.plan("P1", "Input", "M2", record);
  p.on_inform(inform(*id, {"C1", "Input", "M1", 1s}));
  p.on_inform(inform(*id, {"C2", "M1", "M2", 2s}));
  clock.advance(100ms);
  p.tick();
  ASSERT_EQ(results.size(), 1U);
  EXPECT_EQ(results[0]->eta(), 3s);
}

TEST_F(PlannerTest, NoRouteAsksAgainThenFails) {
  auto p = make();
  transport.conveyor_count = 1;
  auto id = p.plan("P1", "Input", "M9", record);
  p.on_inform(inform(*id, {"C1", "Input", "M1", 1s}));  // all conveyors answered: no route
  EXPECT_TRUE(results.empty());
  clock.advance(50ms);
  p.tick();
  ASSERT_EQ(transport.requests.size(), 2U);
  EXPECT_NE(transport.requests[1].conversation, *id);   // a fresh request
  p.on_inform(inform(*id, {"C1", "Input", "M1", 1s}));  // the old request is over
  EXPECT_EQ(p.ignored(), 1U);
  p.on_inform(inform(transport.requests[1].conversation, {"C1", "Input", "M1", 1s}));
  ASSERT_EQ(results.size(), 1U);
  ASSERT_FALSE(results[0].ok());
  EXPECT_EQ(results[0].error().code, Errc::not_found);
}

TEST_F(PlannerTest, DuplicateAndMalformedInformsAreIgnored) {
  auto p = make();
  transport.conveyor_count = 3;
  auto id = p.plan("P1", "Input", "M1", record);
  p.on_inform(inform(*id, {"C1", "Input", "M1", 1s}));
  p.on_inform(inform(*id, {"C1", "Input", "M1", 1s}));
  p.on_inform(inform(*id, {"C2", "M1", "M1", 1s}));
  p.on_inform(inform(*id, {"C3", "", "M1", 1s}));
  EXPECT_EQ(p.ignored(), 3U);
  EXPECT_TRUE(results.empty());
}

// A belt with stations serves a segment per stretch: its answer is complete with its last hop.
TEST_F(PlannerTest, AConveyorOfSeveralSegmentsHasAnsweredWithItsLastHop) {
  auto p = make();
  transport.conveyor_count = 2;
  auto id = p.plan("P1", "conveyor1/upload", "conveyor3/toshiba", record);
  ASSERT_TRUE(id.ok()) << id.error().describe();
  p.on_inform(inform(*id, {"conveyor3", "conveyor3", "conveyor3/toshiba", 5400ms}, 2));
  p.on_inform(inform(*id, {"conveyor1", "conveyor1/upload", "conveyor2", 3400ms}, 2));
  EXPECT_TRUE(results.empty());  // conveyor1 has a second segment to come
  p.on_inform(inform(*id, {"conveyor1", "conveyor1/upload", "conveyor2", 3400ms}, 2));
  EXPECT_EQ(p.ignored(), 1U);  // a duplicate does not complete it
  EXPECT_TRUE(results.empty());
  p.on_inform(inform(*id, {"conveyor1", "conveyor1/upload", "conveyor3", 3400ms}, 2));
  EXPECT_TRUE(results.empty());  // conveyor3 still owes one
  p.on_inform(inform(*id, {"conveyor3", "conveyor3/toshiba", "conveyor4", 1800ms}, 2));
  ASSERT_EQ(results.size(), 1U);
  ASSERT_TRUE(results[0].ok());
  EXPECT_EQ(results[0]->describe(),
            "conveyor1/upload -conveyor1-> conveyor3 -conveyor3-> conveyor3/toshiba (8.800 s)");
}

TEST_F(PlannerTest, SamePlaceNeedsNoRequest) {
  auto p = make();
  ASSERT_TRUE(p.plan("P1", "M1", "M1", record).ok());
  ASSERT_EQ(results.size(), 1U);
  EXPECT_TRUE(results[0]->segments.empty());
  EXPECT_TRUE(transport.requests.empty());
  EXPECT_FALSE(p.plan("P1", "", "M1", record).ok());
}

TEST(ConveyorRole, InformsItsSegmentOncePerRequest) {
  ManualClock clock;
  test::RecordingContractorTransport t;
  auto c = Conveyor::create(t, clock, {"C1", "Input", "M1", 2s});
  ASSERT_TRUE(c.ok());
  c->on_request({"r1", "P1", "Input", "M3", clock.utc_now() + 1s});
  ASSERT_EQ(t.informs.size(), 1U);
  EXPECT_EQ(t.informs[0].conveyor, "C1");
  EXPECT_EQ(t.informs[0].from, "Input");
  EXPECT_EQ(t.informs[0].to, "M1");
  EXPECT_EQ(t.informs[0].transit_time, 2s);
  EXPECT_EQ(t.informs[0].eta, clock.utc_now() + 3s);
  c->on_request({"r1", "P1", "Input", "M3", clock.utc_now()});
  c->on_request({"r2", "P1", "", "M3", clock.utc_now()});
  EXPECT_EQ(t.informs.size(), 1U);
  EXPECT_EQ(c->ignored(), 2U);
  c->on_request_closed("r1");
  EXPECT_EQ(t.closed, std::vector<std::string>{"r1"});
  EXPECT_FALSE(Conveyor::create(t, clock, {"C2", "A", "A", 1s}).ok());
}

// Segments from a real controller (ConveyorBackend): one INFORM per segment, each telling how
// many there are, the ETA after the belt's queue; nothing at all while the backend has none.
class Belt final : public ConveyorBackend {
 public:
  std::vector<Hop> segments(const TransportRequest& /*request*/, std::string& why_not) override {
    if (jammed) {
      why_not = "jammed";
      return {};
    }
    return {{"conveyor4", "conveyor4/denso", 2s, 1s},
            {"conveyor4/denso", "conveyor4/download", 3200ms, 1s},
            {"conveyor4/download", "conveyor4/download", 1s, 0s}};  // not a segment: left out
  }
  bool jammed = false;
};

TEST(ConveyorRole, InformsEveryRealSegmentOrNothing) {
  ManualClock clock;
  test::RecordingContractorTransport t;
  Belt belt;
  ConveyorConfig cfg{"conveyor4", {}, {}, 0s, &belt};
  auto c = Conveyor::create(t, clock, cfg);
  ASSERT_TRUE(c.ok()) << c.error().describe();
  c->on_request({"r1", "P1", "conveyor4", "conveyor4/download", clock.utc_now()});
  ASSERT_EQ(t.informs.size(), 2U);
  EXPECT_EQ(t.informs[1].from, "conveyor4/denso");
  EXPECT_EQ(t.informs[1].to, "conveyor4/download");
  EXPECT_EQ(t.informs[1].transit_time, 3200ms);
  EXPECT_EQ(t.informs[1].eta, clock.utc_now() + 1s + 3200ms);
  EXPECT_EQ(t.informs[0].hops, 2U);
  EXPECT_EQ(t.informs[1].hops, 2U);
  belt.jammed = true;
  c->on_request({"r2", "P1", "conveyor4", "conveyor4/download", clock.utc_now()});
  EXPECT_EQ(t.informs.size(), 2U);
  EXPECT_EQ(c->silent(), 1U);
}

}  // namespace
}  // namespace sf::negotiation
