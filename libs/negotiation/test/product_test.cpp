// The product's parameters: each operation is announced with the plan's
// parameters for it and with what earlier steps' INFORM-DONE told the product
// about itself (the carried results, e.g. its box's id).
#include "sf/negotiation/product.hpp"

#include <gtest/gtest.h>

#include "test_support.hpp"

namespace sf::negotiation {
namespace {

using namespace std::chrono_literals;
using test::bid_at;
using test::from;

class ProductTest : public ::testing::Test {
 protected:
  ProductTest() : manager(transport, clock, config()) { transport.listening = 1; }
  static ManagerConfig config() {
    ManagerConfig c;
    c.incarnation = 0xabc;
    return c;
  }
  // The contractor M1 bids, confirms and reports the last announced conversation done.
  void work(std::vector<Param> results) {
    const Announce& a = transport.announces.back();
    manager.on_contractor_message(from(a.conversation, "M1", 1, bid_at(clock, 10ms), a.operation));
    manager.on_contractor_message(from(a.conversation, "M1", 1, Confirm{1}, a.operation));
    manager.on_contractor_message(
        from(a.conversation, "M1", 1, InformDone{1, "done", std::move(results)}, a.operation));
  }

  ManualClock clock;
  test::RecordingManagerTransport transport;
  Manager manager;
};

TEST_F(ProductTest, AnnouncesThePlansParametersAndCarriesResultsForward) {
  ProductPlan plan{"P1", {"upload", "transport", "load", "download"}, "Input", false};
  plan.params["upload"] = {{"box_type", 1}};
  plan.params["transport"] = {{"from", 1}, {"to", 4}};
  plan.params["download"] = {{"box", 99}};  // its own parameter outranks a carried one
  Product p{manager, nullptr, plan};
  ASSERT_TRUE(p.start());
  EXPECT_EQ(transport.announces.back().params, (std::vector<Param>{{"box_type", 1}}));
  work({{"box", 7}, {"weight_g", 40}});
  ASSERT_EQ(transport.announces.size(), 2U);
  EXPECT_EQ(transport.announces.back().operation, "transport");
  EXPECT_EQ(transport.announces.back().params, (std::vector<Param>{{"from", 1}, {"to", 4}, {"box", 7}}));
  ASSERT_EQ(p.steps().size(), 1U);
  EXPECT_EQ(p.steps()[0].results, (std::vector<Param>{{"box", 7}, {"weight_g", 40}}));
  work({{"box", 8}});  // the latest value is carried
  EXPECT_EQ(transport.announces.back().params, (std::vector<Param>{{"box", 8}}));
  work({});
  EXPECT_EQ(transport.announces.back().params, (std::vector<Param>{{"box", 99}}));
  work({});
  EXPECT_TRUE(p.ok());
}

}  // namespace
}  // namespace sf::negotiation
