// The smart robot in the Contract Net: a product's manager announces "load 3
// of candy T into box B", the robot's contractor bids from the controller's
// planned estimate, the awarded work runs on the plant through our EtherCAT
// master, and the job's end reaches the product as INFORM-DONE (or a FAILURE
// that makes the product negotiate again). In memory, on one ManualClock.
#include "sf/factory/contract_net.hpp"
#include "sf/negotiation/manager.hpp"
#include "sf/negotiation/memory_transport.hpp"
#include "smart_robot_rig.hpp"

namespace sf::factory {
namespace {

using namespace std::chrono_literals;
using testing::kRobot;

class SmartRobotContractNet : public ::testing::Test {
 protected:
  SmartRobotContractNet()
      : rig(/*auto_start=*/true),
        net_(rig_.clock()),
        manager_endpoint_(net_.add_manager()),
        manager_(manager_endpoint_, rig_.clock()),
        backend_(robot_) {
    manager_endpoint_.bind(manager_);
    auto& endpoint = net_.add_contractor(kRobot, {std::string(kLoad)});
    negotiation::ContractorConfig cfg{kRobot, backend_.skills()};
    cfg.backend = &backend_;
    auto c = negotiation::Contractor::create(endpoint, rig_.clock(), cfg);
    EXPECT_TRUE(c) << c.error().describe();
    contractor_.emplace(std::move(*c));
    endpoint.bind(*contractor_);
    backend_.bind(*contractor_);
  }

  void SetUp() override {
    rig.start([this] {
      net_.deliver();
      manager_.tick();
      contractor_->tick();
    });
    ASSERT_TRUE(rig_.run_until([&] { return robot_.status().packml.state == PackMLState::Execute; }, 5s));
  }

  int candy(std::string_view name) const { return rig.candy(name); }
  plant::BoxId place_box() { return rig.place_box(); }

  // Negotiates "load `count` of `candy_name` into `box`" and records how it ends.
  void negotiate(std::string_view candy_name, int count, plant::BoxId box) {
    const auto type = rig.box_type("small-box");
    negotiation::OperationRequest request{"box-" + std::to_string(box),
                                          std::string(kLoad),
                                          {{"candy", static_cast<double>(candy(candy_name))},
                                           {"count", static_cast<double>(count)},
                                           {"box", static_cast<double>(box)},
                                           {"slot", 0},
                                           {"box_type", static_cast<double>(type)}},
                                          ""};
    negotiation::ConversationEvents events;
    events.on_confirmed = [this](const negotiation::Conversation& c) { confirmed_ = c.contractor; };
    events.on_done = [this](const negotiation::Conversation&) { done_ = true; };
    events.on_failed = [this](const negotiation::Conversation&) { failed_ = true; };
    auto id = manager_.negotiate(std::move(request), std::move(events));
    ASSERT_TRUE(id) << id.error().describe();
  }

  testing::SmartRobotRig rig;
  plant::testing::Rig& rig_ = rig.rig;
  SmartRobot& robot_ = rig.robot;
  negotiation::MemoryNetwork net_;
  negotiation::MemoryManagerEndpoint& manager_endpoint_;
  negotiation::Manager manager_;
  ControllerBackend backend_;
  std::optional<negotiation::Contractor> contractor_;
  std::string confirmed_;
  bool done_ = false;
  bool failed_ = false;
};

TEST_F(SmartRobotContractNet, AnAwardedLoadEndsWithTheCandiesInTheBoxAndInformDone) {
  const plant::BoxId box = place_box();
  negotiate("gummy", 3, box);
  ASSERT_TRUE(rig_.run_until([&] { return done_ || failed_; }, 30s));
  EXPECT_TRUE(done_);
  EXPECT_EQ(confirmed_, kRobot);
  const plant::Box* b = rig_.world().box(box);
  ASSERT_NE(b, nullptr);
  for (int slot = 0; slot < 3; ++slot) {
    EXPECT_EQ(b->slots[static_cast<std::size_t>(slot)], candy("gummy")) << "slot " << slot;
  }
  EXPECT_EQ(b->slots[3], -1);
  EXPECT_EQ(robot_.status().packml.produced, 1U);
}

TEST_F(SmartRobotContractNet, ARobotWithAnEmptyDispenserDoesNotBidForThatCandy) {
  const plant::BoxId box = place_box();
  ASSERT_TRUE(rig_.plant().inject(*plant::parse_fault("dispenser-empty:scara1-gummy")));
  negotiate("gummy", 1, box);
  // The pick finds no gummy: FAILURE; the product negotiates again and the
  // robot, its gummy dispenser now known empty, no longer bids.
  ASSERT_TRUE(rig_.run_until([&] { return failed_ || done_; }, 30s));
  EXPECT_TRUE(failed_);
  EXPECT_FALSE(done_);
  EXPECT_EQ(robot_.empty_dispensers().count(static_cast<std::size_t>(candy("gummy"))), 1U);
  EXPECT_EQ(robot_.status().packml.defective, 1U);
  // Another candy still gets bids and is loaded.
  failed_ = false;
  negotiate("chocolate", 1, box);
  ASSERT_TRUE(rig_.run_until([&] { return done_ || failed_; }, 30s));
  EXPECT_TRUE(done_);
}

TEST_F(SmartRobotContractNet, AFaultedRobotFailsTheWorkAndStopsBidding) {
  const plant::BoxId box = place_box();
  negotiate("gummy", 2, box);
  ASSERT_TRUE(rig_.run_until([&] { return robot_.arm().moving(); }, 5s));
  ASSERT_TRUE(rig_.plant().inject(*plant::parse_fault("axis-fault:scara-robot-1:0")));
  ASSERT_TRUE(rig_.run_until([&] { return failed_ || done_; }, 30s));
  EXPECT_TRUE(failed_);
  EXPECT_EQ(robot_.status().packml.state, PackMLState::Aborted);
  std::string why;
  EXPECT_FALSE(robot_.estimate(Operation{std::string(kLoad), {}}, &why));
  EXPECT_NE(why.find("Aborted"), std::string::npos) << why;
}

}  // namespace
}  // namespace sf::factory
