// Every rule of the manager role (see manager.hpp), driven by a ManualClock
// and a recording transport.
#include "sf/negotiation/manager.hpp"

#include <gtest/gtest.h>

#include "test_support.hpp"

namespace sf::negotiation {
namespace {

using namespace std::chrono_literals;
using test::bid_at;
using test::from;

class ManagerTest : public ::testing::Test {
 protected:
  ManagerConfig config() {
    ManagerConfig c;
    c.bid_window = 100ms;
    c.confirm_window = 50ms;
    c.confirm_grace = 20ms;
    c.reannounce_delay = 30ms;
    c.max_rounds = 3;
    c.incarnation = 0xabc;
    return c;
  }

  std::string start(Manager& m, std::string directed = {}) {
    auto id = m.negotiate({"P1", "OP1", {{"speed", 2.0}}, std::move(directed)},
                          {[this](const Conversation& c) { confirmed.push_back(c.contractor); },
                           [this](const Conversation& c) {
                             done.push_back(c.contractor);
                             results = c.results;
                           },
                           [this](const Conversation& c) { failed.push_back(c.failure); }});
    EXPECT_TRUE(id.ok());
    return *id;
  }

  // A lost worker gets 2 s to come back.
  ManagerConfig with_grace(std::chrono::nanoseconds work_timeout) {
    ManagerConfig c = config();
    c.lost_grace = 2s;
    c.work_timeout = work_timeout;
    return c;
  }

  // M1 bids (and M2 when two listen), is awarded and confirms; the conversation's id.
  std::string m1_working(Manager& m, std::size_t listening) {
    transport.listening = listening;
    auto id = start(m);
    m.on_contractor_message(from(id, "M1", 1, bid_at(clock, 10ms)));
    if (listening > 1) {
      m.on_contractor_message(from(id, "M2", 1, bid_at(clock, 20ms)));  // all answered: M1 awarded
    }
    m.on_contractor_message(from(id, "M1", 1, Confirm{1}));
    return id;
  }

  void advance(std::chrono::nanoseconds d, Manager& m) {
    clock.advance(d);
    m.tick();
  }

  ManualClock clock;
  test::RecordingManagerTransport transport;
  std::vector<std::string> confirmed;
  std::vector<std::string> done;
  std::vector<Param> results;  // of the last INFORM-DONE
  std::vector<std::string> failed;
};

TEST_F(ManagerTest, AnnouncesWithRoundParamsAndBidDeadline) {
  Manager m{transport, clock, config()};
  const auto id = start(m);
  EXPECT_EQ(id, "P1/OP1/abc.1");
  ASSERT_EQ(transport.announces.size(), 1U);
  const auto& a = transport.announces[0];
  EXPECT_EQ(a.conversation, id);
  EXPECT_EQ(a.product, "P1");
  EXPECT_EQ(a.operation, "OP1");
  EXPECT_EQ(a.round, 1U);
  EXPECT_EQ(a.params, (std::vector<Param>{{"speed", 2.0}}));
  EXPECT_EQ(a.bid_deadline, clock.utc_now() + 100ms);
  EXPECT_EQ(m.find(id)->phase, Phase::Collecting);
  EXPECT_EQ(m.next_deadline(), clock.now() + 100ms);
}

// The agent loop sleeps until next_deadline(): a timer the conversation left behind would wake it
// for nothing.
TEST_F(ManagerTest, NextDeadlineIsTheEarliestLiveTimer) {
  Manager m{transport, clock, config()};
  transport.listening = 1;
  const auto first = start(m);
  clock.advance(10ms);
  const auto second = start(m);
  EXPECT_EQ(m.next_deadline(), clock.now() + 90ms);  // the first's bid deadline
  m.on_contractor_message(from(first, "M1", 1, bid_at(clock, 10ms)));
  EXPECT_EQ(m.next_deadline(), clock.now() + 70ms);  // its confirm_by + grace, before the second's
  m.on_contractor_message(from(first, "M1", 1, Confirm{1}));
  EXPECT_EQ(m.next_deadline(), clock.now() + 100ms);  // working without a timeout: the second's
  m.on_contractor_message(from(second, "M1", 1, bid_at(clock, 10ms)));
  m.on_contractor_message(from(second, "M1", 1, Confirm{1}));
  EXPECT_EQ(m.next_deadline(), std::nullopt);
  m.on_contractor_message(from(first, "M1", 1, InformDone{1, "ok"}));
  m.on_contractor_message(from(second, "M1", 1, InformDone{1, "ok"}));
  EXPECT_EQ(m.next_deadline(), std::nullopt);
  EXPECT_EQ(done.size(), 2U);
}

TEST_F(ManagerTest, RejectsBadRequests) {
  Manager m{transport, clock, config()};
  EXPECT_FALSE(m.negotiate({"P 1", "OP1", {}, {}}).ok());
  EXPECT_FALSE(m.negotiate({"P1", "OP-1", {}, {}}).ok());
  EXPECT_FALSE(m.negotiate({"P1", "OP1", std::vector<Param>(9), {}}).ok());
  EXPECT_TRUE(transport.announces.empty());
}

TEST_F(ManagerTest, WaitsForTheDeadlineThenAwardsTheBestBid) {
  Manager m{transport, clock, config()};
  transport.listening = 3;
  const auto id = start(m);
  m.on_contractor_message(from(id, "M1", 1, bid_at(clock, 300ms)));
  m.on_contractor_message(from(id, "M2", 1, bid_at(clock, 200ms)));
  advance(99ms, m);
  EXPECT_TRUE(transport.sent.empty());  // M3 may still bid
  advance(1ms, m);
  ASSERT_EQ(transport.sent.size(), 1U);
  const auto& award = transport.sent[0];
  EXPECT_EQ(award.contractor, "M2");
  EXPECT_EQ(std::get<Award>(award.body).award_id, 1U);
  EXPECT_EQ(std::get<Award>(award.body).confirm_by, clock.utc_now() + 50ms);
  EXPECT_EQ(m.find(id)->phase, Phase::Awarding);
}

TEST_F(ManagerTest, ClosesBiddingEarlyWhenEveryListeningContractorAnswered) {
  Manager m{transport, clock, config()};
  transport.listening = 2;
  const auto id = start(m);
  m.on_contractor_message(from(id, "M1", 1, bid_at(clock, 300ms)));
  EXPECT_TRUE(transport.sent.empty());
  m.on_contractor_message(from(id, "M2", 1, Refuse{0, "busy"}));  // a decline counts as an answer
  ASSERT_EQ(transport.sent.size(), 1U);
  EXPECT_EQ(transport.sent[0].contractor, "M1");
}

TEST_F(ManagerTest, ConfirmStartsWorkAndInformDoneEndsTheConversation) {
  Manager m{transport, clock, config()};
  transport.listening = 1;
  const auto id = start(m);
  clock.advance(3ms);
  m.on_contractor_message(from(id, "M1", 1, bid_at(clock, 10ms)));
  clock.advance(2ms);
  m.on_contractor_message(from(id, "M1", 1, Confirm{1}));
  EXPECT_EQ(confirmed, std::vector<std::string>{"M1"});
  const Conversation* c = m.find(id);
  ASSERT_NE(c, nullptr);
  EXPECT_EQ(c->phase, Phase::Working);
  EXPECT_EQ(c->confirmed_at - c->started_at, 5ms);
  m.on_contractor_message(from(id, "M1", 1, InformDone{1, "ok", {{"box", 7}}}));
  EXPECT_EQ(done, std::vector<std::string>{"M1"});
  EXPECT_EQ(results, (std::vector<Param>{{"box", 7}}));  // the product learns what it needs
  EXPECT_EQ(m.find(id), nullptr);
  EXPECT_EQ(transport.closed, std::vector<std::string>{id});
  EXPECT_EQ(m.stats().done, 1U);
}

TEST_F(ManagerTest, BidsAfterTheDeadlineAreIgnored) {
  Manager m{transport, clock, config()};
  transport.listening = 2;
  const auto id = start(m);
  m.on_contractor_message(from(id, "M1", 1, bid_at(clock, 900ms)));
  advance(100ms, m);                                               // deadline: award M1
  m.on_contractor_message(from(id, "M2", 1, bid_at(clock, 1ms)));  // better, but late
  EXPECT_EQ(m.last_ignored(), "bid after the deadline");
  ASSERT_EQ(transport.of_kind<Award>().size(), 1U);
  EXPECT_EQ(transport.of_kind<Award>()[0].contractor, "M1");
}

TEST_F(ManagerTest, ABidArrivingAtTheDeadlineBeforeTheTimerRanIsLate) {
  Manager m{transport, clock, config()};
  transport.listening = 2;
  const auto id = start(m);
  clock.advance(100ms);  // deadline reached, tick() not yet called
  m.on_contractor_message(from(id, "M2", 1, bid_at(clock, 1ms)));
  EXPECT_EQ(m.last_ignored(), "bid after the deadline");
  m.tick();
  EXPECT_TRUE(transport.of_kind<Award>().empty());
}

TEST_F(ManagerTest, ReannouncesWhenNoBidArrivesAndFailsAfterMaxRounds) {
  Manager m{transport, clock, config()};
  const auto id = start(m);
  advance(100ms, m);
  EXPECT_EQ(m.find(id)->phase, Phase::Waiting);
  EXPECT_EQ(transport.announces.size(), 1U);
  advance(30ms, m);
  ASSERT_EQ(transport.announces.size(), 2U);
  EXPECT_EQ(transport.announces[1].round, 2U);
  EXPECT_EQ(transport.announces[1].conversation, id);  // same instance, next round
  // A bid for round 1 is now stale.
  m.on_contractor_message(from(id, "M1", 1, bid_at(clock, 1ms)));
  EXPECT_EQ(m.last_ignored(), "bid for round 1, current round is 2");
  advance(100ms, m);
  advance(30ms, m);
  EXPECT_EQ(transport.announces.size(), 3U);
  advance(100ms, m);
  advance(30ms, m);
  EXPECT_EQ(transport.announces.size(), 3U);  // max_rounds = 3
  ASSERT_EQ(failed.size(), 1U);
  EXPECT_NE(failed[0].find("after 3 announcements"), std::string::npos);
  EXPECT_EQ(m.find(id), nullptr);
  EXPECT_EQ(transport.closed, std::vector<std::string>{id});
}

TEST_F(ManagerTest, UnlimitedRoundsKeepAnnouncing) {
  auto cfg = config();
  cfg.max_rounds = 0;
  Manager m{transport, clock, cfg};
  start(m);
  for (int i = 0; i < 20; ++i) {
    advance(100ms, m);
    advance(30ms, m);
  }
  EXPECT_EQ(transport.announces.size(), 21U);
  EXPECT_TRUE(failed.empty());
}

TEST_F(ManagerTest, RefusalMovesTheAwardToTheNextBest) {
  Manager m{transport, clock, config()};
  transport.listening = 3;
  const auto id = start(m);
  m.on_contractor_message(from(id, "M1", 1, bid_at(clock, 10ms)));
  m.on_contractor_message(from(id, "M2", 1, bid_at(clock, 20ms)));
  m.on_contractor_message(from(id, "M3", 1, bid_at(clock, 30ms)));
  ASSERT_EQ(transport.sent.back().contractor, "M1");
  m.on_contractor_message(from(id, "M1", 1, Refuse{1, "broken"}));
  ASSERT_EQ(transport.sent.size(), 2U);
  EXPECT_EQ(transport.sent[1].contractor, "M2");
  EXPECT_EQ(std::get<Award>(transport.sent[1].body).award_id, 2U);
  m.on_contractor_message(from(id, "M2", 1, Confirm{2}));
  EXPECT_EQ(confirmed, std::vector<std::string>{"M2"});
}

TEST_F(ManagerTest, ConfirmationTimeoutCancelsAndAwardsTheNextBest) {
  Manager m{transport, clock, config()};
  transport.listening = 2;
  const auto id = start(m);
  m.on_contractor_message(from(id, "M1", 1, bid_at(clock, 10ms)));
  m.on_contractor_message(from(id, "M2", 1, bid_at(clock, 20ms)));
  advance(69ms, m);  // confirm_window 50 + grace 20
  EXPECT_EQ(transport.sent.size(), 1U);
  advance(1ms, m);
  ASSERT_EQ(transport.sent.size(), 3U);
  EXPECT_EQ(transport.sent[1].contractor, "M1");
  EXPECT_EQ(std::get<Cancel>(transport.sent[1].body).award_id, 1U);
  EXPECT_EQ(transport.sent[2].contractor, "M2");
  EXPECT_EQ(std::get<Award>(transport.sent[2].body).award_id, 2U);
}

TEST_F(ManagerTest, NeverTwoLiveAwardsAndALateConfirmIsCancelled) {
  Manager m{transport, clock, config()};
  transport.listening = 2;
  const auto id = start(m);
  m.on_contractor_message(from(id, "M1", 1, bid_at(clock, 10ms)));
  m.on_contractor_message(from(id, "M2", 1, bid_at(clock, 20ms)));
  // While M1's award is live, nothing else is awarded, whatever arrives.
  m.on_contractor_message(from(id, "M2", 1, Confirm{1}));
  EXPECT_EQ(transport.of_kind<Award>().size(), 1U);
  advance(70ms, m);  // M1 lapses, M2 gets award 2
  ASSERT_EQ(transport.of_kind<Award>().size(), 2U);
  // M1 confirms award 1 too late: not accepted, and told to stop.
  m.on_contractor_message(from(id, "M1", 1, Confirm{1}));
  EXPECT_TRUE(confirmed.empty());
  EXPECT_EQ(m.last_ignored(), "confirmation of an award that is not live");
  const auto cancels = transport.of_kind<Cancel>();
  ASSERT_EQ(cancels.size(), 2U);
  EXPECT_EQ(cancels[1].contractor, "M1");
  EXPECT_EQ(std::get<Cancel>(cancels[1].body).award_id, 1U);
  m.on_contractor_message(from(id, "M2", 1, Confirm{2}));
  EXPECT_EQ(confirmed, std::vector<std::string>{"M2"});
}

TEST_F(ManagerTest, AllCandidatesRefusingLeadsToANewRound) {
  Manager m{transport, clock, config()};
  transport.listening = 1;
  const auto id = start(m);
  m.on_contractor_message(from(id, "M1", 1, bid_at(clock, 10ms)));
  m.on_contractor_message(from(id, "M1", 1, Refuse{1, "changed my mind"}));
  EXPECT_EQ(m.find(id)->phase, Phase::Waiting);
  advance(30ms, m);
  EXPECT_EQ(transport.announces.size(), 2U);
}

TEST_F(ManagerTest, LostAwardeeIsSkippedAndLostWorkerTriggersRenegotiation) {
  Manager m{transport, clock, config()};
  transport.listening = 3;
  const auto id = start(m);
  m.on_contractor_message(from(id, "M1", 1, bid_at(clock, 10ms)));
  m.on_contractor_message(from(id, "M2", 1, bid_at(clock, 20ms)));
  m.on_contractor_message(from(id, "M3", 1, bid_at(clock, 30ms)));
  m.on_contractor_lost("OP1", "M1");  // awarded, not yet confirmed
  auto awards = transport.of_kind<Award>();
  ASSERT_EQ(awards.size(), 2U);
  EXPECT_EQ(awards[1].contractor, "M2");
  m.on_contractor_message(from(id, "M2", 1, Confirm{2}));
  ASSERT_EQ(confirmed, std::vector<std::string>{"M2"});
  m.on_contractor_lost("OP1", "M2");  // dies while working
  ASSERT_EQ(transport.announces.size(), 2U);
  EXPECT_EQ(transport.announces[1].round, 2U);
  EXPECT_EQ(m.find(id)->renegotiations, 1U);
  // The old award is withdrawn in case M2 is alive after all.
  EXPECT_EQ(transport.sent.back().contractor, "M2");
  EXPECT_TRUE(std::holds_alternative<Cancel>(transport.sent.back().body));
  // A FAILURE of the withdrawn award (the CANCEL reached M2) changes nothing.
  m.on_contractor_message(from(id, "M2", 1, Failure{2, "cancelled"}));
  EXPECT_TRUE(done.empty());
  EXPECT_EQ(transport.announces.size(), 2U);
  m.on_contractor_message(from(id, "M3", 2, bid_at(clock, 5ms)));
  advance(100ms, m);
  m.on_contractor_message(from(id, "M3", 2, Confirm{3}));
  m.on_contractor_message(from(id, "M3", 2, InformDone{3, "ok"}));
  EXPECT_EQ(done, std::vector<std::string>{"M3"});
}

TEST_F(ManagerTest, ALostWorkerThatComesBackWithinItsGraceKeepsItsWork) {
  Manager m{transport, clock, with_grace(10s)};
  const auto id = m1_working(m, 2);
  const auto sent = transport.sent.size();
  // Liveliness lost, regained a second later: no CANCEL, no new round, not even after the grace.
  m.on_contractor_lost("OP1", "M1");
  advance(1s, m);
  m.on_contractor_alive("OP1", "M1");
  advance(2s, m);
  EXPECT_EQ(transport.sent.size(), sent);
  EXPECT_EQ(transport.announces.size(), 1U);
  EXPECT_EQ(m.find(id)->phase, Phase::Working);
  // Lost again, and its INFORM-DONE within the grace is the proof of life.
  m.on_contractor_lost("OP1", "M1");
  advance(1500ms, m);
  m.on_contractor_message(from(id, "M1", 1, InformDone{1, "ok"}));
  EXPECT_EQ(done, std::vector<std::string>{"M1"});
  EXPECT_EQ(m.stats().renegotiations, 0U);
}

TEST_F(ManagerTest, ALostWorkerNotBackWithinItsGraceIsReplacedAndTheWorkTimeoutStillHolds) {
  Manager m{transport, clock, with_grace(3s)};
  const auto id = m1_working(m, 1);
  m.on_contractor_lost("OP1", "M1");
  advance(1999ms, m);
  EXPECT_EQ(transport.announces.size(), 1U);
  advance(1ms, m);
  ASSERT_EQ(transport.announces.size(), 2U);
  EXPECT_TRUE(std::holds_alternative<Cancel>(transport.sent.back().body));
  EXPECT_EQ(transport.sent.back().contractor, "M1");

  // A worker back in time still has to finish within the work timeout.
  m.on_contractor_message(from(id, "M1", 2, bid_at(clock, 10ms)));
  m.on_contractor_message(from(id, "M1", 2, Confirm{2}));
  m.on_contractor_lost("OP1", "M1");
  advance(500ms, m);
  m.on_contractor_alive("OP1", "M1");
  advance(2499ms, m);
  EXPECT_EQ(transport.announces.size(), 2U);
  advance(1ms, m);
  EXPECT_EQ(transport.announces.size(), 3U);
}

// A worker cut off for longer than its grace (a network partition) goes on working; its
// INFORM-DONE arrives once the network is back. Its work is done: the conversation ends with it,
// and the machine the work was given to meanwhile is told to stop before it does it a second time.
TEST_F(ManagerTest, AWorkerGivenUpOnThatReportsItsWorkDoneEndsTheConversation) {
  Manager m{transport, clock, with_grace(0s)};
  const auto id = m1_working(m, 2);
  m.on_contractor_lost("OP1", "M1");
  advance(2s, m);  // the grace is over: M1's award 1 withdrawn, round 2
  ASSERT_EQ(transport.announces.size(), 2U);
  m.on_contractor_message(from(id, "M2", 2, bid_at(clock, 10ms)));
  advance(100ms, m);
  m.on_contractor_message(from(id, "M2", 2, Confirm{2}));
  ASSERT_EQ(confirmed, (std::vector<std::string>{"M1", "M2"}));

  m.on_contractor_alive("OP1", "M1");
  m.on_contractor_message(from(id, "M1", 1, InformDone{1, "loaded", {{"box", 7.0}}}));
  EXPECT_EQ(done, std::vector<std::string>{"M1"});
  EXPECT_EQ(results, (std::vector<Param>{{"box", 7.0}}));
  EXPECT_EQ(m.find(id), nullptr);
  EXPECT_EQ(transport.sent.back().contractor, "M2");
  EXPECT_EQ(std::get<Cancel>(transport.sent.back().body).award_id, 2U);
  EXPECT_EQ(transport.announces.size(), 2U);
  // M2's answer to the CANCEL comes to a finished conversation.
  m.on_contractor_message(from(id, "M2", 2, Failure{2, "cancelled"}));
  EXPECT_EQ(m.last_ignored(), "unknown or finished conversation");
  EXPECT_TRUE(failed.empty());
}

// The same INFORM-DONE while the operation is still being announced: nobody else has it yet.
TEST_F(ManagerTest, AWorkerGivenUpOnThatReportsDoneWhileAnnouncingEndsTheConversation) {
  Manager m{transport, clock, with_grace(0s)};
  const auto id = m1_working(m, 1);
  m.on_contractor_lost("OP1", "M1");
  advance(2s, m);
  ASSERT_EQ(m.find(id)->phase, Phase::Collecting);
  const auto cancels = transport.of_kind<Cancel>().size();
  // Another contractor's INFORM-DONE for M1's award proves nothing.
  m.on_contractor_message(from(id, "M2", 1, InformDone{1, "ok"}));
  EXPECT_EQ(m.last_ignored(), "INFORM-DONE for an award that is not being worked");
  m.on_contractor_message(from(id, "M1", 1, InformDone{1, "ok"}));
  EXPECT_EQ(done, std::vector<std::string>{"M1"});
  EXPECT_EQ(transport.of_kind<Cancel>().size(), cancels);
  EXPECT_EQ(transport.closed.size(), 1U);
}

TEST_F(ManagerTest, LostBidderIsNotAwarded) {
  Manager m{transport, clock, config()};
  transport.listening = 3;
  const auto id = start(m);
  m.on_contractor_message(from(id, "M1", 1, bid_at(clock, 10ms)));
  m.on_contractor_lost("OP1", "M1");
  m.on_contractor_lost("OP2", "M9");  // another operation: no effect here
  m.on_contractor_message(from(id, "M2", 1, bid_at(clock, 20ms)));
  advance(100ms, m);
  const auto awards = transport.of_kind<Award>();
  ASSERT_EQ(awards.size(), 1U);
  EXPECT_EQ(awards[0].contractor, "M2");
}

TEST_F(ManagerTest, FailureTriggersRenegotiation) {
  Manager m{transport, clock, config()};
  transport.listening = 1;
  const auto id = start(m);
  m.on_contractor_message(from(id, "M1", 1, bid_at(clock, 10ms)));
  m.on_contractor_message(from(id, "M1", 1, Confirm{1}));
  m.on_contractor_message(from(id, "M1", 1, Failure{1, "jammed"}));
  EXPECT_EQ(transport.announces.size(), 2U);
  EXPECT_EQ(m.stats().renegotiations, 1U);
  EXPECT_EQ(m.find(id)->phase, Phase::Collecting);
}

TEST_F(ManagerTest, WorkTimeoutRenegotiates) {
  auto cfg = config();
  cfg.work_timeout = 1s;
  Manager m{transport, clock, cfg};
  transport.listening = 1;
  const auto id = start(m);
  m.on_contractor_message(from(id, "M1", 1, bid_at(clock, 10ms)));
  m.on_contractor_message(from(id, "M1", 1, Confirm{1}));
  advance(999ms, m);
  EXPECT_EQ(transport.announces.size(), 1U);
  advance(1ms, m);
  EXPECT_EQ(transport.announces.size(), 2U);
}

TEST_F(ManagerTest, DuplicatesAndOutOfOrderMessagesAreIgnored) {
  Manager m{transport, clock, config()};
  transport.listening = 2;
  const auto id = start(m);
  // Out of order: a CONFIRM and an INFORM-DONE before any award.
  m.on_contractor_message(from(id, "M1", 1, Confirm{1}));
  m.on_contractor_message(from(id, "M1", 1, InformDone{1, "ok"}));
  m.on_contractor_message(from(id, "M1", 1, Refuse{1, "?"}));
  m.on_contractor_message(from(id, "M1", 1, bid_at(clock, 10ms)));
  m.on_contractor_message(from(id, "M1", 1, bid_at(clock, 1ms)));  // duplicate answer
  EXPECT_EQ(m.last_ignored(), "duplicate answer in this round");
  EXPECT_EQ(m.find(id)->bids.at("M1").estimated_finish, clock.utc_now() + 10ms);
  m.on_contractor_message(from(id, "M2", 1, Refuse{0, "busy"}));
  m.on_contractor_message(from(id, "M2", 1, Refuse{0, "busy"}));
  m.on_contractor_message(from(id, "M1", 1, Confirm{1}));
  m.on_contractor_message(from(id, "M1", 1, Confirm{1}));
  EXPECT_EQ(m.last_ignored(), "duplicate confirmation");
  EXPECT_EQ(confirmed.size(), 1U);
  m.on_contractor_message(from(id, "M1", 1, InformDone{1, "ok"}));
  m.on_contractor_message(from(id, "M1", 1, InformDone{1, "ok"}));
  EXPECT_EQ(m.last_ignored(), "unknown or finished conversation");
  EXPECT_EQ(done.size(), 1U);
  m.on_contractor_message(from("P9/OP1/1.1", "M1", 1, bid_at(clock, 1ms)));
  m.on_contractor_message(from(id, "M1", 1, bid_at(clock, 1ms), "OP2"));
  EXPECT_GE(m.stats().ignored, 8U);
}

TEST_F(ManagerTest, MessageForAnotherOperationIsIgnored) {
  Manager m{transport, clock, config()};
  const auto id = start(m);
  m.on_contractor_message(from(id, "M1", 1, bid_at(clock, 10ms), "OP7"));
  EXPECT_EQ(m.last_ignored(), "operation OP7 does not match the conversation's OP1");
  EXPECT_TRUE(m.find(id)->bids.empty());
}

TEST_F(ManagerTest, DirectedAwardConfirmedWithoutAnnouncement) {
  Manager m{transport, clock, config()};
  const auto id = start(m, "M7");
  EXPECT_TRUE(transport.announces.empty());
  ASSERT_EQ(transport.sent.size(), 1U);
  const auto& d = std::get<DirectedAward>(transport.sent[0].body);
  EXPECT_EQ(transport.sent[0].contractor, "M7");
  EXPECT_EQ(d.award_id, 1U);
  EXPECT_EQ(d.params, (std::vector<Param>{{"speed", 2.0}}));
  m.on_contractor_message(from(id, "M7", 0, Confirm{1}));
  EXPECT_EQ(confirmed, std::vector<std::string>{"M7"});
}

TEST_F(ManagerTest, DirectedAwardRefusedOrUnconfirmedFallsBackToAnnounce) {
  Manager m{transport, clock, config()};
  const auto a = start(m, "M7");
  m.on_contractor_message(from(a, "M7", 0, Refuse{1, "busy"}));
  ASSERT_EQ(transport.announces.size(), 1U);
  EXPECT_EQ(transport.announces[0].conversation, a);
  const auto b = start(m, "M8");
  advance(70ms, m);
  ASSERT_EQ(transport.announces.size(), 2U);
  EXPECT_EQ(transport.announces[1].conversation, b);
  EXPECT_EQ(transport.of_kind<Cancel>().back().contractor, "M8");
}

TEST_F(ManagerTest, FailingTransportRetriesTheAnnouncement) {
  Manager m{transport, clock, config()};
  transport.fail = true;
  const auto id = start(m);
  EXPECT_EQ(m.find(id)->phase, Phase::Waiting);
  transport.fail = false;
  advance(30ms, m);
  EXPECT_EQ(transport.announces.size(), 1U);
  EXPECT_EQ(m.find(id)->phase, Phase::Collecting);
}

}  // namespace
}  // namespace sf::negotiation
