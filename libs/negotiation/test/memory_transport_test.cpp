// The in-memory network's faults that the state machines' tests rely on, seen from the inboxes.
#include "sf/negotiation/memory_transport.hpp"

#include <gtest/gtest.h>

#include "test_support.hpp"

namespace sf::negotiation {
namespace {

using namespace std::chrono_literals;
using test::from;

struct ManagerSide final : ManagerInbox {
  void on_contractor_message(const ContractorMessage& m) override { messages.push_back(m.conversation); }
  void on_contractor_lost(const std::string& op, const std::string& c) override {
    lost.push_back(op + " " + c);
  }
  void on_contractor_alive(const std::string& op, const std::string& c) override {
    alive.push_back(op + " " + c);
  }
  std::vector<std::string> messages;
  std::vector<std::string> lost;
  std::vector<std::string> alive;
};

struct ContractorSide final : ContractorInbox {
  void on_announce(const Announce& a) override { received.push_back("announce " + a.conversation); }
  void on_manager_message(const ManagerMessage& m) override { received.push_back("award " + m.conversation); }
  void on_conversation_closed(const std::string& /*op*/, const std::string& c) override {
    received.push_back("closed " + c);
  }
  std::vector<std::string> received;
};

// A contractor cut off the network works on: nothing it sends, nor anything sent to it, is lost;
// it all arrives in its order once it is reconnected. Managers see its liveliness lost after the
// lease, and back at the reconnection, before what waited.
TEST(MemoryNetwork, ACutOffContractorsTrafficWaitsAndItsLivelinessIsLostThenBack) {
  ManualClock clock;
  MemoryNetwork net{clock, MemoryNetworkOptions{.lease = 1s}};
  auto& manager_end = net.add_manager();
  auto& contractor_end = net.add_contractor("M1", {"OP1"});
  ManagerSide manager;
  ContractorSide contractor;
  manager_end.bind(manager);
  contractor_end.bind(contractor);

  net.cut_off("M1");
  ASSERT_TRUE(manager_end.announce({"P1/OP1/1.1", "P1", "OP1", 1, {}, clock.utc_now() + 1s}));
  ASSERT_TRUE(contractor_end.send(from("P1/OP1/1.0", "M1", 1, InformDone{1, "done"})));
  ASSERT_TRUE(manager_end.send({"P1/OP1/1.1", "P1", "OP1", "M1", 1, Cancel{1, "lost"}}));
  manager_end.close("OP1", "P1/OP1/1.1");
  net.deliver();
  EXPECT_TRUE(contractor.received.empty());
  EXPECT_TRUE(manager.messages.empty());
  EXPECT_EQ(manager_end.contractors("OP1"), 1U);  // until the lease expires
  clock.advance(1s);
  net.deliver();
  EXPECT_EQ(manager.lost, std::vector<std::string>{"OP1 M1"});
  EXPECT_EQ(manager_end.contractors("OP1"), 0U);

  net.reconnect("M1");
  EXPECT_EQ(manager.alive, std::vector<std::string>{"OP1 M1"});
  EXPECT_TRUE(manager.messages.empty());  // liveliness first, then what waited
  net.deliver();
  net.deliver();
  EXPECT_EQ(manager.messages, std::vector<std::string>{"P1/OP1/1.0"});
  EXPECT_EQ(contractor.received,
            (std::vector<std::string>{"announce P1/OP1/1.1", "award P1/OP1/1.1", "closed P1/OP1/1.1"}));
  EXPECT_EQ(manager_end.contractors("OP1"), 1U);

  // A cut shorter than the lease is not noticed, and a killed contractor gets nothing that waited.
  net.cut_off("M1");
  clock.advance(500ms);
  net.reconnect("M1");
  clock.advance(1s);
  net.deliver();
  EXPECT_EQ(manager.lost.size(), 1U);
  net.cut_off("M1");
  ASSERT_TRUE(manager_end.announce({"P1/OP1/1.2", "P1", "OP1", 1, {}, clock.utc_now() + 1s}));
  net.deliver();
  net.kill("M1");
  net.reconnect("M1");
  net.deliver();
  net.deliver();
  EXPECT_EQ(contractor.received.size(), 3U);
  EXPECT_EQ(net.stats().dropped, 1U);
}

}  // namespace
}  // namespace sf::negotiation
