// Names, topic names and selection policies.
#include "sf/negotiation/messages.hpp"

#include <gtest/gtest.h>

#include "sf/negotiation/selection.hpp"

namespace sf::negotiation {
namespace {

using namespace std::chrono_literals;

TEST(Messages, TopicNamesFollowThePaper) {
  EXPECT_EQ(announce_topic("OP1"), "OP1_ANNOUNCE");
  EXPECT_EQ(bid_topic("OP1"), "OP1_BID");
  EXPECT_EQ(award_topic("OP1"), "OP1_AWARD");
  EXPECT_EQ(kRequestTopic, "REQUEST");
  EXPECT_EQ(kInformTopic, "INFORM");
}

TEST(Messages, OperationListsAreValidated) {
  auto ops = parse_operations("OP1,Pick_2,OP3");
  ASSERT_TRUE(ops.ok());
  EXPECT_EQ(*ops, (std::vector<std::string>{"OP1", "Pick_2", "OP3"}));
  EXPECT_FALSE(parse_operations("").ok());
  EXPECT_FALSE(parse_operations("OP1,,OP2").ok());
  EXPECT_FALSE(parse_operations("OP1,OP1").ok());
  EXPECT_FALSE(parse_operations("OP-1").ok());
  EXPECT_FALSE(parse_operations(std::string(23, 'A')).ok());  // OPx_ANNOUNCE must fit 31
  EXPECT_TRUE(parse_operations(std::string(22, 'A')).ok());
  EXPECT_FALSE(validate_name("machine", "M 1").ok());
  EXPECT_FALSE(validate_name("machine", std::string(32, 'M')).ok());
  EXPECT_TRUE(validate_name("machine", "robot-1.a_b").ok());
}

TEST(Messages, KindsAndDescriptions) {
  const ContractorMessage m{"P1/OP1/1.1", "M2", "OP1", 1, Confirm{3}};
  EXPECT_EQ(kind_name(m.body), "CONFIRM");
  EXPECT_EQ(award_of(m.body), 3U);
  EXPECT_EQ(describe(m), "CONFIRM P1/OP1/1.1 from M2 (OP1 round 1 award 3)");
  EXPECT_EQ(kind_name(ContractorBody{InformDone{}}), "INFORM-DONE");
  EXPECT_EQ(kind_name(ManagerBody{DirectedAward{}}), "DIRECTEDAWARD");
  EXPECT_EQ(award_of(ContractorBody{Bid{}}), 0U);
}

std::vector<std::string> order(const SelectionPolicy& p, const std::vector<RankedBid>& bids) {
  std::vector<std::string> out;
  for (const auto& b : rank(p, bids)) {
    out.push_back(b.contractor);
  }
  return out;
}

TEST(Messages, LocationsMayNameABeltsStation) {
  EXPECT_TRUE(validate_location("conveyor3/toshiba").ok());
  EXPECT_TRUE(validate_location("Input").ok());
  EXPECT_FALSE(validate_location("").ok());
  EXPECT_FALSE(validate_location("conveyor 3").ok());
  EXPECT_FALSE(validate_location(std::string(kMaxName + 1, 'c')).ok());
  EXPECT_FALSE(validate_name("machine", "conveyor3/toshiba").ok());  // names stay without '/'
}

// Reasons and results come from controllers and their devices: too long for the wire, they are
// cut (never inside a UTF-8 sequence) rather than the message lost.
TEST(Messages, TextIsCutToTheWireBound) {
  EXPECT_EQ(fit_text("jammed"), "jammed");
  EXPECT_EQ(fit_text(std::string(200, 'r')), std::string(kMaxText, 'r'));
  const std::string degrees =
      std::string(kMaxText - 1, 'x') + "\u00B0C";  // "°" (2 bytes) straddles the bound
  EXPECT_EQ(fit_text(degrees), std::string(kMaxText - 1, 'x'));
}

TEST(Selection, PoliciesRankAsNamed) {
  const UtcTime t0{};
  const std::vector<RankedBid> bids{
      {"A", {t0, t0 + 30s, 1.0, 5}}, {"B", {t0, t0 + 10s, 9.0, 2}}, {"C", {t0, t0 + 20s, 3.0, 0}}};
  EXPECT_EQ(order(earliest_finish(), bids), (std::vector<std::string>{"B", "C", "A"}));
  EXPECT_EQ(order(lowest_cost(), bids), (std::vector<std::string>{"A", "C", "B"}));
  EXPECT_EQ(order(load_balance(), bids), (std::vector<std::string>{"C", "B", "A"}));
}

TEST(Selection, TiesAreBrokenByNameAndPoliciesAreFoundByName) {
  const UtcTime t0{};
  const std::vector<RankedBid> bids{{"Z", {t0, t0 + 1s, 1.0, 0}}, {"A", {t0, t0 + 1s, 1.0, 0}}};
  EXPECT_EQ(order(earliest_finish(), bids), (std::vector<std::string>{"A", "Z"}));
  EXPECT_EQ(policy_by_name("lowest-cost")->name, "lowest-cost");
  EXPECT_FALSE(policy_by_name("cheapest").ok());
}

}  // namespace
}  // namespace sf::negotiation
