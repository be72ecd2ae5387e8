// The DDS endpoints over real DDS (loopback, a partition private to the test):
// an instance's end reaches a reader as a key-only sample, which carries the
// key hashes only, and the endpoints still report which conversation ended; a
// sample whose hash is not its conversation's is dropped.
#include <gtest/gtest.h>
#include <unistd.h>

#include <functional>
#include <string>
#include <utility>
#include <vector>

#include <fmt/format.h>

#include "dds_common.hpp"
#include "sf/core/clock.hpp"

namespace sf::negotiation {
namespace {

using namespace std::chrono_literals;

struct RecordingMachine final : ContractorInbox {
  void on_announce(const Announce& a) override { announced.push_back(a.conversation); }
  void on_manager_message(const ManagerMessage& m) override { told.push_back(m.conversation); }
  void on_conversation_closed(const std::string& operation, const std::string& conversation) override {
    closed.emplace_back(operation, conversation);
  }
  std::vector<std::string> announced;
  std::vector<std::string> told;
  std::vector<std::pair<std::string, std::string>> closed;
};

struct RecordingManager final : ManagerInbox {
  void on_contractor_message(const ContractorMessage& m) override { heard.push_back(m.contractor); }
  void on_contractor_lost(const std::string& operation, const std::string& contractor) override {
    lost.emplace_back(operation, contractor);
  }
  std::vector<std::string> heard;
  std::vector<std::pair<std::string, std::string>> lost;
};

struct RecordingConveyor final : ConveyorInbox {
  void on_request(const TransportRequest& r) override { requested.push_back(r.conversation); }
  void on_request_closed(const std::string& conversation) override { closed.push_back(conversation); }
  std::vector<std::string> requested;
  std::vector<std::string> closed;
};

class DdsEndpointsTest : public ::testing::Test {
 protected:
  void SetUp() override {
    settings.machining_domain = 76;
    settings.conveying_domain = 75;
    settings.partition = fmt::format("sf-endpoints-{}-{}", ::getpid(),
                                     ::testing::UnitTest::GetInstance()->current_test_info()->name());
    product = ProductEndpoints::create(settings, "P1", {"OP1"}, executor, clock).value();
    machine = MachineEndpoints::create(settings, "M1", {"OP1"}, executor, clock).value();
    conveyor = ConveyorEndpoints::create(settings, "C1", executor).value();
    machine->bind(machine_inbox);
    conveyor->bind(conveyor_inbox);
    ASSERT_TRUE(pump([&] { return product->contractors("OP1") == 1 && product->conveyors() == 1; }))
        << "the machine and the conveyor were not discovered";
  }

  // Runs delivered messages until `done` or 10 s.
  bool pump(const std::function<bool()>& done) {
    const auto until = std::chrono::steady_clock::now() + 10s;
    while (!done()) {
      if (std::chrono::steady_clock::now() > until) {
        return false;
      }
      executor.wait_for(10ms);
      const auto strand = executor.hold();
      executor.run_pending();
    }
    return true;
  }

  DdsSettings settings;
  ManualClock clock;
  dds::Executor executor;
  RecordingMachine machine_inbox;
  RecordingConveyor conveyor_inbox;
  std::unique_ptr<ProductEndpoints> product;
  std::unique_ptr<MachineEndpoints> machine;
  std::unique_ptr<ConveyorEndpoints> conveyor;
};

TEST_F(DdsEndpointsTest, TheEndOfAnInstanceNamesItsConversation) {
  const std::string c1 = "P1/OP1/ab.1";
  const std::string c2 = "P1/OP1/ab.2";
  const std::string r1 = "P1/route/ab.3";
  for (const auto& c : {c1, c2}) {
    ASSERT_TRUE(product->announce({c, "P1", "OP1", 1, {}, clock.utc_now() + 1s}).ok());
  }
  ASSERT_TRUE(product->send({c1, "P1", "OP1", "M1", 1, Award{1, clock.utc_now() + 1s}}).ok());
  ASSERT_TRUE(product->request({r1, "P1", "A", "B", clock.utc_now()}).ok());
  ASSERT_TRUE(pump([&] {
    return machine_inbox.announced.size() == 2 && machine_inbox.told.size() == 1 &&
           conveyor_inbox.requested.size() == 1;
  }));

  product->close("OP1", c1);
  product->close(r1);
  clock.advance(detail::kEndDelay);
  product->flush_ended();
  // c1 ends on both topics it used (ANNOUNCE and AWARD); c2 goes on.
  const std::vector<std::pair<std::string, std::string>> c1_twice{{"OP1", c1}, {"OP1", c1}};
  ASSERT_TRUE(pump([&] { return machine_inbox.closed.size() >= 2 && !conveyor_inbox.closed.empty(); }));
  EXPECT_EQ(machine_inbox.closed, c1_twice);
  EXPECT_EQ(conveyor_inbox.closed, std::vector<std::string>{r1});

  product->close("OP1", c2);
  clock.advance(detail::kEndDelay);
  product->flush_ended();
  ASSERT_TRUE(pump([&] { return machine_inbox.closed.size() >= 3; }));
  EXPECT_EQ(machine_inbox.closed.back(), std::make_pair(std::string{"OP1"}, c2));
}

// Every machine of OP1 reads OP1_AWARD, but takes in only what is addressed to it (a content
// filter): M1 never hears of M2's award and cancel, nor of their conversation's end.
TEST_F(DdsEndpointsTest, AMachineTakesInOnlyTheAwardsAddressedToIt) {
  RecordingMachine m2_inbox;
  auto m2 = MachineEndpoints::create(settings, "M2", {"OP1"}, executor, clock).value();
  m2->bind(m2_inbox);
  ASSERT_TRUE(pump([&] { return product->contractors("OP1") == 2; }));
  const std::string c1 = "P1/OP1/ab.1";
  const std::string c2 = "P1/OP1/ab.2";
  ASSERT_TRUE(product->send({c1, "P1", "OP1", "M2", 1, Award{1, clock.utc_now() + 1s}}).ok());
  ASSERT_TRUE(product->send({c1, "P1", "OP1", "M2", 1, Cancel{1, "withdrawn"}}).ok());
  ASSERT_TRUE(product->send({c2, "P1", "OP1", "M1", 1, Award{1, clock.utc_now() + 1s}}).ok());
  // One writer's samples arrive in order: once M1 has c2, it has been offered c1's two.
  ASSERT_TRUE(pump([&] { return machine_inbox.told.size() == 1 && m2_inbox.told.size() == 2; }));
  EXPECT_EQ(machine_inbox.told, std::vector<std::string>{c2});
  EXPECT_EQ(m2_inbox.told, (std::vector<std::string>{c1, c1}));

  product->close("OP1", c1);
  product->close("OP1", c2);
  clock.advance(detail::kEndDelay);
  product->flush_ended();
  ASSERT_TRUE(pump([&] { return !machine_inbox.closed.empty() && !m2_inbox.closed.empty(); }));
  using Closed = std::vector<std::pair<std::string, std::string>>;
  EXPECT_EQ(machine_inbox.closed, (Closed{{"OP1", c2}}));
  EXPECT_EQ(m2_inbox.closed, (Closed{{"OP1", c1}}));
}

TEST_F(DdsEndpointsTest, ASampleWhoseKeyHashIsNotItsConversationsIsDropped) {
  dds::Participant p = detail::join(settings, settings.machining_domain, "rogue").value();
  auto topic = dds::Topic<sf_cnp_Announce>::create(p, announce_topic("OP1")).value();
  auto writer = dds::Writer<sf_cnp_Announce>::create(p, topic, detail::writer_qos(settings)).value();
  codec::ParamStorage storage;
  auto bad = codec::encode(Announce{"P9/OP1/x.1", "P9", "OP1", 1, {}, clock.utc_now() + 1s}, storage).value();
  bad.conversation_hash = codec::key_hash("P9/OP1/x.2");
  ASSERT_TRUE(writer.write(bad).ok());
  const auto good =
      codec::encode(Announce{"P9/OP1/x.3", "P9", "OP1", 1, {}, clock.utc_now() + 1s}, storage).value();
  ASSERT_TRUE(writer.write(good).ok());
  // Samples of one writer arrive in order: once the good one is in, the bad one was handled.
  ASSERT_TRUE(pump([&] { return !machine_inbox.announced.empty(); }));
  EXPECT_EQ(machine_inbox.announced, std::vector<std::string>{"P9/OP1/x.3"});
}

// A machine's OPx_BID writer has MANUAL_BY_TOPIC liveliness: it stays alive while the machine's
// agent asserts it, without any BID, and once the agent stops asserting the product presumes the
// machine dead after the lease, although its process and Cyclone's threads still run.
TEST_F(DdsEndpointsTest, AMachineIsAliveWhileItsAgentAssertsAndLostOnceItStops) {
  RecordingManager manager;
  product->bind(manager);
  DdsSettings s = settings;
  s.liveliness_lease = 1s;
  auto m2 = MachineEndpoints::create(s, "M2", {"OP1"}, executor, clock).value();
  ASSERT_TRUE(pump([&] { return product->bidders("OP1") == 2; }));
  const Bid bid{clock.utc_now(), clock.utc_now() + 1s, 1.0, 0};
  ASSERT_TRUE(m2->send({"P1/OP1/ab.1", "M2", "OP1", 1, bid}).ok());
  ASSERT_TRUE(pump([&] { return manager.heard.size() == 1; }));

  // Three leases of agent turns without a BID; the agent's clock follows the real one, which
  // Cyclone's lease runs on.
  auto last = std::chrono::steady_clock::now();
  const auto until = last + 3s;
  const auto turn = [&] {
    const auto now = std::chrono::steady_clock::now();
    clock.advance(now - last);
    last = now;
    m2->assert_liveliness();
    return now > until;
  };
  ASSERT_TRUE(pump(turn));
  EXPECT_TRUE(manager.lost.empty()) << "lost while asserting";

  ASSERT_TRUE(pump([&] { return !manager.lost.empty(); })) << "not lost after it stopped asserting";
  EXPECT_EQ(manager.lost, (std::vector<std::pair<std::string, std::string>>{{"OP1", "M2"}}));
}

// A reader's memory of conversations lasts as long as their instances.
TEST(OpenConversations, RemembersAnInstanceUntilItEnds) {
  const auto log = log::get("negotiation");
  detail::OpenConversations open{"OP1_ANNOUNCE"};
  open.opened(1, "a", log);
  open.opened(1, "a", log);  // a re-announcement: the same instance
  open.opened(2, "b", log);
  EXPECT_EQ(open.size(), 2U);
  EXPECT_EQ(open.closed(1), "a");
  EXPECT_EQ(open.closed(1), std::nullopt);  // ended already, or never seen alive
  EXPECT_EQ(open.size(), 1U);
  open.opened(2, "c", log);  // two live conversations with one hash: the newer owns the instance
  EXPECT_EQ(open.closed(2), "c");
  EXPECT_EQ(open.size(), 0U);
}

}  // namespace
}  // namespace sf::negotiation
