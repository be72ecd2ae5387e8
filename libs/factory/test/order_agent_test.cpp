// The order agent's steps on a scripted Contract Net: the test plays the machines and conveyors
// (who confirms, who reports done, which route comes back, and when), so orderings that a line
// shows only now and then happen on purpose.
#include "sf/factory/order_agent.hpp"

#include <algorithm>

#include <gtest/gtest.h>

#include <fmt/format.h>

#include "sf/factory/machine.hpp"

namespace sf::factory {
namespace {

using namespace std::chrono_literals;
namespace cnp = sf::negotiation;

// Decisions as the test makes them. Routes are checked as the RoutePlanner checks them.
class ScriptedDecisions final : public ProductDecisions {
 public:
  struct Negotiation {
    cnp::OperationRequest request;
    cnp::ConversationEvents events;
  };
  struct Plan {
    std::string from;
    std::string to;
    cnp::RouteCallback done;
  };

  Result<std::string> negotiate(cnp::OperationRequest request, cnp::ConversationEvents events) override {
    negotiations.push_back({std::move(request), std::move(events)});
    return fmt::format("c{}", negotiations.size());
  }
  Result<std::string> plan(const std::string& /*product*/, const std::string& from, const std::string& to,
                           cnp::RouteCallback done) override {
    SF_TRY(cnp::validate_location(from));
    SF_TRY(cnp::validate_location(to));
    plans.push_back({from, to, std::move(done)});
    return fmt::format("r{}", plans.size());
  }

  cnp::Conversation conversation(std::size_t n, const std::string& contractor) const {
    cnp::Conversation c;
    c.id = fmt::format("c{}", n + 1);
    c.operation = negotiations.at(n).request.operation;
    c.contractor = contractor;
    c.round = 1;
    return c;
  }
  void confirm(std::size_t n, const std::string& contractor) {
    negotiations.at(n).events.on_confirmed(conversation(n, contractor));
  }
  void done(std::size_t n, const std::string& contractor, std::vector<cnp::Param> results = {}) {
    auto c = conversation(n, contractor);
    c.results = std::move(results);
    negotiations.at(n).events.on_done(c);
  }
  void route(std::size_t n, std::vector<cnp::Segment> segments) {
    const Plan& p = plans.at(n);
    p.done(cnp::Route{p.from, p.to, std::move(segments)});
  }

  std::vector<Negotiation> negotiations;
  std::vector<Plan> plans;
};

class OrderAgentTest : public ::testing::Test {
 protected:
  std::shared_ptr<OrderAgent> start(Order order) {
    auto agent = OrderAgent::create(std::move(order), "o-1.1", {&layout, &decisions, &clock, &belts}, {},
                                    [this](const OrderEvent& e) { events.push_back(e); });
    EXPECT_TRUE(agent->start());
    return agent;
  }
  [[nodiscard]] std::size_t count(std::string_view what) const {
    return static_cast<std::size_t>(
        std::count_if(events.begin(), events.end(), [&](const OrderEvent& e) { return e.what == what; }));
  }

  line::Layout layout = *line::default_layout();
  ManualClock clock;
  ScriptedDecisions decisions;
  BeltBlocks belts;
  std::vector<OrderEvent> events;
};

// SCARA Robot 1 loads the box, then is cut off the network: its load goes to the TOSHIBA, and the
// box sets off towards it. The robot's INFORM-DONE arrives when its link is back: the load is done,
// and the download negotiated. The box's transport ends at the next belt before the downloader
// confirmed: the box waits there, no route is asked to nowhere, and once the downloader confirms
// there is one route to it, and only one.
TEST_F(OrderAgentTest, AStepDoneWhileItsBoxIsOnTheWayToAnotherMachineStopsTheBoxAndGoesOn) {
  auto agent = start({"o-1", "small-box", {{"gummy", 1}}});
  decisions.confirm(0, "uploader");
  decisions.done(0, "uploader", {{"box", 1.0}});
  ASSERT_EQ(decisions.negotiations.size(), 2U);
  EXPECT_EQ(decisions.negotiations[1].request.operation, kLoad);
  decisions.confirm(1, "scara-robot-1");
  ASSERT_EQ(decisions.plans.size(), 1U);
  EXPECT_EQ(decisions.plans[0].to, "conveyor2/scara1");
  decisions.route(0, {{"conveyor1", "conveyor1/upload", "conveyor2", 3s},
                      {"conveyor2", "conveyor2", "conveyor2/scara1", 3s}});
  decisions.done(2, "conveyor1");
  decisions.done(3, "conveyor2");
  EXPECT_EQ(agent->location(), "conveyor2/scara1");

  decisions.confirm(1, "toshiba");  // the load negotiated again
  ASSERT_EQ(decisions.plans.size(), 2U);
  decisions.route(1, {{"conveyor2", "conveyor2/scara1", "conveyor4", 3s},
                      {"conveyor4", "conveyor4", "conveyor5", 3s},
                      {"conveyor5", "conveyor5", "conveyor1", 3s},
                      {"conveyor1", "conveyor1", "conveyor3", 3s},
                      {"conveyor3", "conveyor3", "conveyor3/toshiba", 3s}});
  ASSERT_EQ(decisions.negotiations.size(), 5U);  // conveyor 2 carries the box off
  decisions.done(1, "scara-robot-1");            // the robot's late INFORM-DONE
  ASSERT_EQ(decisions.negotiations.size(), 6U);
  EXPECT_EQ(decisions.negotiations[5].request.operation, kDownload);
  EXPECT_EQ(count("loaded"), 1U);

  decisions.done(4, "conveyor2");  // the box at conveyor 4's entry, no downloader yet
  EXPECT_EQ(agent->location(), "conveyor4");
  EXPECT_EQ(decisions.plans.size(), 2U);
  EXPECT_EQ(decisions.negotiations.size(), 6U);
  decisions.confirm(5, "downloader");
  ASSERT_EQ(decisions.plans.size(), 3U);
  EXPECT_EQ(decisions.plans[2].from, "conveyor4");
  EXPECT_EQ(decisions.plans[2].to, "conveyor4/download");
  clock.advance(2s);
  agent->tick();
  EXPECT_EQ(decisions.plans.size(), 3U);
  EXPECT_EQ(count("retry"), 0U);

  decisions.route(2, {{"conveyor4", "conveyor4", "conveyor4/download", 3s}});
  decisions.done(6, "conveyor4");
  EXPECT_EQ(agent->location(), "conveyor4/download");
  decisions.done(5, "downloader", {{"box", 1.0}, {"weight_g", 42.5}, {"count.gummy", 1.0}});
  EXPECT_TRUE(agent->ok()) << agent->failure();
  EXPECT_EQ(count("done"), 1U);
}

}  // namespace
}  // namespace sf::factory
