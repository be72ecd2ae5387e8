// The gateways in the Contract Net against the plant's PLCs, over the
// in-memory negotiation transport: a product gets its box uploaded, carried
// along routes the conveyors' real segments make, loaded by the legacy robot
// and downloaded; a gateway whose PLC is unreachable, whose belt is held or
// whose dispenser ran empty does not bid; a job that fails on the line is a
// FAILURE to the product.
#include "contract_net_rig.hpp"

namespace sf::factory::testing {
namespace {

using S = PackMLState;

bool mentions(const std::vector<std::string>& texts, std::string_view part) {
  return std::any_of(texts.begin(), texts.end(),
                     [&](const std::string& t) { return t.find(part) != std::string::npos; });
}

TEST(GatewayContractNet, AProductsBoxIsUploadedCarriedLoadedAndDownloaded) {
  GatewayRig rig;
  ContractNetRig cnp(rig);
  for (const char* belt : {"conveyor1", "conveyor2", "conveyor3", "conveyor4"}) {
    cnp.add(belt, "conveyor");
  }
  cnp.add("uploader", "uploader");
  cnp.add("toshiba", "legacy-robot");
  cnp.add("downloader", "downloader");
  rig.run_for(100ms);

  const Negotiated up = cnp.negotiate("upload", {{"box_type", 0}});
  ASSERT_TRUE(up.ok) << up.failure;
  EXPECT_EQ(up.contractor, "uploader");
  const auto box = static_cast<std::uint16_t>(up.results.at("box"));  // INFORM-DONE's typed result
  EXPECT_TRUE(rig.at(box, "conveyor1/upload"));

  // The route to the robot's station from the belts' own segments: conveyor1 hands the box
  // over to conveyor3 through its diverter, conveyor3 carries it to the robot.
  auto to_robot = cnp.route("conveyor1/upload", "conveyor3/toshiba");
  ASSERT_TRUE(to_robot) << to_robot.error().describe();
  EXPECT_EQ(to_robot->describe(),
            "conveyor1/upload -conveyor1-> conveyor3 -conveyor3-> conveyor3/toshiba (8.800 s)");
  const Negotiated carried = cnp.carry(box, *to_robot);
  ASSERT_TRUE(carried.ok) << carried.failure;
  EXPECT_EQ(carried.contractor, "conveyor3");
  EXPECT_TRUE(rig.at(box, "conveyor3/toshiba"));

  const Negotiated load = cnp.negotiate("load", {{"candy", static_cast<double>(rig.candy("gummy"))},
                                                 {"count", 2},
                                                 {"box", static_cast<double>(box)},
                                                 {"slot", 0}});
  ASSERT_TRUE(load.ok) << load.failure;
  EXPECT_EQ(load.contractor, "toshiba");
  EXPECT_EQ(load.results.at("placed"), 2);

  auto to_download = cnp.route("conveyor3/toshiba", "conveyor4/download");
  ASSERT_TRUE(to_download) << to_download.error().describe();
  ASSERT_EQ(to_download->segments.size(), 3U);  // conveyor4's two hops become one transport
  ASSERT_TRUE(cnp.carry(box, *to_download).ok);

  const Negotiated down = cnp.negotiate("download", {{"box", static_cast<double>(box)}});
  ASSERT_TRUE(down.ok) << down.failure;
  EXPECT_EQ(down.results.at("box"), box);
  EXPECT_EQ(down.results.at("count.gummy"), 2);
  EXPECT_EQ(down.results.at("weight_g"), 45.0);  // tare 40 g + 2 × 2.5 g
  EXPECT_EQ(rig.world().box(box), nullptr);      // off the line
  EXPECT_EQ(cnp.manager().stats().renegotiations, 0U);
}

TEST(GatewayContractNet, AGatewayWhosePlcIsUnreachableDoesNotBidUntilItIsBack) {
  GatewayRig rig;
  ContractNetRig cnp(rig);
  Gateway& up = cnp.add("uploader", "uploader");
  rig.run_for(100ms);
  rig.inject("plc-unreachable:uploader");
  ASSERT_TRUE(rig.run_until([&] { return !up.link_up(); }, 1s));
  const Negotiated lost = cnp.negotiate("upload", {{"box_type", 0}});
  EXPECT_FALSE(lost.ok);
  EXPECT_TRUE(mentions(cnp.heard().reasons<cnp::Refuse>("uploader"), "uploader does not answer"));

  rig.clear("plc-unreachable:uploader");
  ASSERT_TRUE(rig.run_until([&] { return up.status().packml.state == S::Execute; }, 2s));
  const Negotiated back = cnp.negotiate("upload", {{"box_type", 0}});
  EXPECT_TRUE(back.ok) << back.failure;
}

// A conveyor that takes no work does not answer REQUESTs: the route goes around its belt.
TEST(GatewayContractNet, RoutesAvoidABeltThatIsHeld) {
  GatewayRig rig;
  ContractNetRig cnp(rig);
  for (const char* belt : {"conveyor1", "conveyor2", "conveyor3", "conveyor4"}) {
    cnp.add(belt, "conveyor");
  }
  rig.run_for(100ms);
  auto fast = cnp.route("conveyor1/upload", "conveyor4/download");
  ASSERT_TRUE(fast) << fast.error().describe();
  EXPECT_EQ(fast->segments[1].conveyor, "conveyor2");

  Gateway& c2 = rig.gateway("conveyor2");
  ASSERT_TRUE(c2.command(PackMLCommand::Hold));
  rig.run_for(100ms);
  auto around = cnp.route("conveyor1/upload", "conveyor4/download");
  ASSERT_TRUE(around) << around.error().describe();
  EXPECT_EQ(around->segments[1].conveyor, "conveyor3");
}

// The dispenser runs empty during the load: FAILURE with the robot's reason; asked again, the
// robot declines that candy.
TEST(GatewayContractNet, AJobThatFailsOnTheLineIsAFailureToTheProduct) {
  GatewayRig rig;
  ContractNetRig cnp(rig);
  cnp.add("toshiba", "legacy-robot");
  const auto box = rig.put_box("conveyor3/toshiba");
  rig.run_for(100ms);
  rig.inject("dispenser-empty:toshiba-toffee");
  const Negotiated load = cnp.negotiate("load", {{"candy", static_cast<double>(rig.candy("toffee"))},
                                                 {"count", 2},
                                                 {"box", static_cast<double>(box)},
                                                 {"slot", 0}});
  EXPECT_FALSE(load.ok);
  const auto failures = cnp.heard().reasons<cnp::Failure>("toshiba");
  ASSERT_EQ(failures.size(), 1U);
  EXPECT_NE(failures[0].find("dispenser empty"), std::string::npos) << failures[0];
  EXPECT_TRUE(mentions(cnp.heard().reasons<cnp::Refuse>("toshiba"), "toffee dispenser ran empty"));
}

}  // namespace
}  // namespace sf::factory::testing
