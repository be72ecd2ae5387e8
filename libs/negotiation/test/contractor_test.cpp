// Every rule of the contractor role (see contractor.hpp).
#include "sf/negotiation/contractor.hpp"

#include <gtest/gtest.h>

#include "test_support.hpp"

namespace sf::negotiation {
namespace {

using namespace std::chrono_literals;

class ContractorTest : public ::testing::Test {
 protected:
  Contractor make(ContractorConfig cfg = {}) {
    if (cfg.name.empty()) {
      cfg.name = "M1";
      cfg.skills = {{"OP1", 100ms, 2.0}, {"OP2", 50ms, 1.0}};
      cfg.speed = 2.0;
      cfg.capacity = 2;
    }
    auto c =
        Contractor::create(transport, clock, std::move(cfg),
                           {[this](const Announce& a) { bids.push_back(a.conversation); },
                            [this](const ManagerMessage& m) { awards.push_back(m.conversation); },
                            {},
                            [this](const Job& j) { started.push_back(j.conversation); },
                            [this](const Job& j, bool ok) { finished.emplace_back(j.conversation, ok); },
                            [this](const Job& j, const std::string&) { aborted.push_back(j.conversation); }});
    EXPECT_TRUE(c.ok()) << c.error().describe();
    return std::move(*c);
  }

  Announce announce(const std::string& conv, std::uint32_t round = 1, const std::string& op = "OP1") {
    return Announce{conv, "P1", op, round, {}, clock.utc_now() + 100ms};
  }
  ManagerMessage award(const std::string& conv, std::uint32_t id, std::uint32_t round = 1,
                       const std::string& to = "M1", const std::string& op = "OP1") {
    return ManagerMessage{conv, "P1", op, to, round, Award{id, clock.utc_now() + 50ms}};
  }
  ManagerMessage cancel(const std::string& conv, std::uint32_t id) {
    return ManagerMessage{conv, "P1", "OP1", "M1", 1, Cancel{id, "lapsed"}};
  }

  ManualClock clock;
  test::RecordingContractorTransport transport;
  std::vector<std::string> bids, awards, started, aborted;
  std::vector<std::pair<std::string, bool>> finished;
};

TEST_F(ContractorTest, RejectsBadConfiguration) {
  test::RecordingContractorTransport t;
  EXPECT_FALSE(Contractor::create(t, clock, {"", {{"OP1"}}}).ok());
  EXPECT_FALSE(Contractor::create(t, clock, {"M1", {}}).ok());
  EXPECT_FALSE(Contractor::create(t, clock, {"M1", {{"OP 1"}}}).ok());
  ContractorConfig slow{"M1", {{"OP1"}}};
  slow.speed = 0.0;
  EXPECT_FALSE(Contractor::create(t, clock, slow).ok());
}

TEST_F(ContractorTest, BidsWithQueueBasedEstimates) {
  auto c = make();
  c.on_announce(announce("a"));
  ASSERT_EQ(transport.sent.size(), 1U);
  const auto& m = transport.sent[0];
  EXPECT_EQ(m.contractor, "M1");
  EXPECT_EQ(m.operation, "OP1");
  EXPECT_EQ(m.round, 1U);
  const auto& b = std::get<Bid>(m.body);
  EXPECT_EQ(b.estimated_start, clock.utc_now());
  EXPECT_EQ(b.estimated_finish, clock.utc_now() + 50ms);  // 100 ms at speed 2
  EXPECT_DOUBLE_EQ(b.cost, 0.05 * 2.0);
  EXPECT_EQ(b.queue_length, 0U);
  EXPECT_EQ(bids, std::vector<std::string>{"a"});
  // Once it works "a", a bid for "b" starts when "a" ends.
  c.on_manager_message(award("a", 1));
  clock.advance(10ms);
  c.on_announce(announce("b"));
  const auto& b2 = std::get<Bid>(transport.sent.back().body);
  EXPECT_EQ(b2.estimated_start, clock.utc_now() + 40ms);
  EXPECT_EQ(b2.estimated_finish, clock.utc_now() + 90ms);
  EXPECT_EQ(b2.queue_length, 1U);
}

TEST_F(ContractorTest, IgnoresUnknownOperationsExpiredAndRepeatedAnnouncements) {
  auto c = make();
  c.on_announce(announce("a", 1, "OP9"));
  EXPECT_EQ(c.last_ignored(), "unknown operation type OP9");
  auto late = announce("b");
  clock.advance(101ms);
  c.on_announce(late);
  EXPECT_EQ(c.last_ignored(), "past its bid deadline");
  c.on_announce(announce("c", 2));
  c.on_announce(announce("c", 2));
  c.on_announce(announce("c", 1));
  EXPECT_EQ(c.last_ignored(), "duplicate or out-of-order round");
  EXPECT_EQ(transport.sent.size(), 1U);
  c.on_announce(announce("c", 3));  // a newer round is bid again
  EXPECT_EQ(transport.sent.size(), 2U);
  EXPECT_EQ(c.stats().ignored, 4U);
}

TEST_F(ContractorTest, ConfirmsAnAwardAndOnlyThenStartsWork) {
  auto c = make();
  c.on_announce(announce("a"));
  EXPECT_TRUE(started.empty());
  c.on_manager_message(award("a", 1));
  ASSERT_EQ(transport.sent.size(), 2U);
  EXPECT_EQ(std::get<Confirm>(transport.sent[1].body).award_id, 1U);
  EXPECT_EQ(started, std::vector<std::string>{"a"});
  EXPECT_EQ(awards, std::vector<std::string>{"a"});
}

TEST_F(ContractorTest, AwardsToOthersAreNotOurs) {
  auto c = make();
  c.on_announce(announce("a"));
  c.on_manager_message(award("a", 1, 1, "M2"));
  EXPECT_EQ(transport.sent.size(), 1U);
  EXPECT_TRUE(started.empty());
  EXPECT_EQ(c.stats().ignored, 0U);
}

TEST_F(ContractorTest, RefusesAwardsItCannotHonour) {
  auto c = make();
  c.on_manager_message(award("nobid", 1));
  EXPECT_EQ(std::get<Refuse>(transport.sent.back().body).reason, "no bid in this conversation");
  c.on_announce(announce("r", 2));
  c.on_manager_message(award("r", 1, 1));
  EXPECT_EQ(std::get<Refuse>(transport.sent.back().body).reason, "award for round 1, bid was for round 2");
  c.on_announce(announce("late"));
  auto a = award("late", 1);
  clock.advance(51ms);
  c.on_manager_message(a);
  EXPECT_EQ(std::get<Refuse>(transport.sent.back().body).reason, "award arrived after its confirm-by time");
  EXPECT_EQ(std::get<Refuse>(transport.sent.back().body).award_id, 1U);
  EXPECT_TRUE(started.empty());
  EXPECT_EQ(c.stats().refusals, 3U);
}

TEST_F(ContractorTest, FullQueueDeclinesCallsAndRefusesAwards) {
  auto c = make();  // capacity 2
  for (const auto* conv : {"a", "b", "x"}) {
    c.on_announce(announce(conv));
  }
  c.on_manager_message(award("a", 1));
  c.on_manager_message(award("b", 1));
  c.on_announce(announce("c"));
  EXPECT_EQ(std::get<Refuse>(transport.sent.back().body).award_id, 0U);
  EXPECT_EQ(std::get<Refuse>(transport.sent.back().body).reason, "queue full");
  c.on_manager_message(award("x", 1));
  EXPECT_EQ(std::get<Refuse>(transport.sent.back().body).reason, "queue full");
  EXPECT_EQ(c.jobs().size(), 2U);
}

TEST_F(ContractorTest, DuplicateAwardIsNotWorkedTwice) {
  auto c = make();
  c.on_announce(announce("a"));
  c.on_manager_message(award("a", 1));
  c.on_manager_message(award("a", 1));
  EXPECT_EQ(c.last_ignored(), "duplicate or stale award");
  EXPECT_EQ(transport.of_kind<Confirm>().size(), 1U);
  EXPECT_EQ(c.jobs().size(), 1U);
}

TEST_F(ContractorTest, WorksJobsInOrderAndReportsDone) {
  auto c = make();
  c.on_announce(announce("a"));
  c.on_announce(announce("b", 1, "OP2"));
  c.on_manager_message(award("a", 1));
  c.on_manager_message(award("b", 1, 1, "M1", "OP2"));
  EXPECT_EQ(started, std::vector<std::string>{"a"});
  EXPECT_EQ(c.next_deadline(), clock.now() + 50ms);
  clock.advance(49ms);
  c.tick();
  EXPECT_TRUE(finished.empty());
  clock.advance(30ms);  // a done at 50, b (25 ms) started at 50, done at 75
  c.tick();
  ASSERT_EQ(finished.size(), 2U);
  EXPECT_EQ(finished[0], std::make_pair(std::string{"a"}, true));
  EXPECT_EQ(finished[1], std::make_pair(std::string{"b"}, true));
  EXPECT_EQ(started, (std::vector<std::string>{"a", "b"}));
  const auto dones = transport.of_kind<InformDone>();
  ASSERT_EQ(dones.size(), 2U);
  EXPECT_EQ(dones[1].operation, "OP2");
  EXPECT_TRUE(c.jobs().empty());
}

// Work that takes no time is done when it starts: INFORM-DONE follows the CONFIRM from the
// handler of the award, without waiting for the next tick (a wake-up of the agent's thread).
TEST_F(ContractorTest, WorkThatTakesNoTimeIsDoneWithItsConfirmation) {
  auto c = make({"M1", {{"OP1", 0ms, 1.0}}, 1.0, 2});
  c.on_announce(announce("a"));
  c.on_manager_message(award("a", 1));
  ASSERT_EQ(transport.sent.size(), 3U);
  EXPECT_EQ(std::get<Confirm>(transport.sent[1].body).award_id, 1U);
  EXPECT_EQ(std::get<InformDone>(transport.sent[2].body).award_id, 1U);
  EXPECT_EQ(finished, (std::vector<std::pair<std::string, bool>>{{"a", true}}));
  EXPECT_TRUE(c.jobs().empty());
  EXPECT_EQ(c.next_deadline(), std::nullopt);
}

TEST_F(ContractorTest, CancelAbortsTheJobAndStartsTheNext) {
  auto c = make();
  c.on_announce(announce("a"));
  c.on_announce(announce("b"));
  c.on_manager_message(award("a", 1));
  c.on_manager_message(award("b", 1));
  c.on_manager_message(cancel("a", 2));  // not our award id: ignored
  EXPECT_EQ(c.last_ignored(), "cancel of an award not worked here");
  c.on_manager_message(cancel("a", 1));
  EXPECT_EQ(aborted, std::vector<std::string>{"a"});
  EXPECT_EQ(started, (std::vector<std::string>{"a", "b"}));
  clock.advance(100ms);
  c.tick();
  ASSERT_EQ(finished.size(), 1U);
  EXPECT_EQ(finished[0].first, "b");
  EXPECT_TRUE(transport.of_kind<InformDone>().size() == 1U);
}

TEST_F(ContractorTest, ReannouncementOfAWorkedConversationDropsTheJob) {
  auto c = make();
  c.on_announce(announce("a"));
  c.on_manager_message(award("a", 1));
  c.on_announce(announce("a", 2));
  EXPECT_EQ(aborted, std::vector<std::string>{"a"});
  EXPECT_TRUE(std::holds_alternative<Bid>(transport.sent.back().body));
  EXPECT_EQ(transport.sent.back().round, 2U);
}

TEST_F(ContractorTest, ClosedConversationIsForgottenAndItsInstanceDisposed) {
  auto c = make();
  c.on_announce(announce("a"));
  c.on_conversation_closed("OP1", "a");
  EXPECT_EQ(transport.closed, std::vector<std::string>{"a"});
  c.on_conversation_closed("OP1", "a");  // twice (ANNOUNCE and AWARD disposed): once is enough
  EXPECT_EQ(transport.closed.size(), 1U);
  c.on_manager_message(award("a", 1));
  EXPECT_TRUE(std::holds_alternative<Refuse>(transport.sent.back().body));
}

TEST_F(ContractorTest, DirectedAwardNeedsNoBid) {
  auto c = make();
  c.on_manager_message(
      ManagerMessage{"d", "P1", "OP2", "M1", 0, DirectedAward{1, clock.utc_now() + 10ms, {}}});
  EXPECT_EQ(std::get<Confirm>(transport.sent.back().body).award_id, 1U);
  EXPECT_EQ(started, std::vector<std::string>{"d"});
  c.on_manager_message(
      ManagerMessage{"e", "P1", "OP9", "M1", 0, DirectedAward{1, clock.utc_now() + 10ms, {}}});
  EXPECT_EQ(c.last_ignored(), "unknown operation type OP9");
}

TEST_F(ContractorTest, FailureProbabilityOneAlwaysFails) {
  ContractorConfig cfg{"M1", {{"OP1", 10ms}}};
  cfg.failure_probability = 1.0;
  auto c = make(cfg);
  c.on_announce(announce("a"));
  c.on_manager_message(award("a", 1));
  clock.advance(10ms);
  c.tick();
  ASSERT_EQ(transport.of_kind<Failure>().size(), 1U);
  EXPECT_EQ(finished[0].second, false);
}

TEST_F(ContractorTest, ForgetsOldBids) {
  ContractorConfig cfg{"M1", {{"OP1", 10ms}}};
  cfg.bid_memory = 1s;
  auto c = make(cfg);
  c.on_announce(announce("a"));
  clock.advance(2s);
  c.tick();
  c.on_manager_message(award("a", 1));
  EXPECT_EQ(std::get<Refuse>(transport.sent.back().body).reason, "no bid in this conversation");
}

// A shop-floor controller behind the contractor (WorkBackend): what it answers and does is
// recorded here; the contractor's side of the protocol is what is checked.
class RecordingBackend final : public WorkBackend {
 public:
  std::optional<WorkEstimate> estimate(const std::string& operation, const std::vector<Param>& params,
                                       std::string& why_not) override {
    asked.push_back(operation);
    last_params = params;
    if (!willing) {
      why_not = "held by the operator";
      return std::nullopt;
    }
    return WorkEstimate{200ms, 1500ms, 3};
  }
  Status start(const Job& job, const std::vector<Param>& params) override {
    started.push_back(job.conversation);
    start_params = params;
    if (fail_start) {
      return make_error(Errc::state, "no box at the station");
    }
    return {};
  }
  void abort(const Job& job, const std::string& why) override { aborted.emplace_back(job.conversation, why); }

  bool willing = true;
  bool fail_start = false;
  std::vector<std::string> asked, started;
  std::vector<std::pair<std::string, std::string>> aborted;
  std::vector<Param> last_params, start_params;
};

TEST_F(ContractorTest, ABackendsEstimateIsTheBidAndItsRefusalADecline) {
  RecordingBackend backend;
  ContractorConfig cfg{"M1", {{"OP1", 100ms, 2.0}}};
  cfg.backend = &backend;
  auto c = make(cfg);
  auto a = announce("a");
  a.params = {{"candy", 2}, {"count", 3}};
  c.on_announce(a);
  ASSERT_EQ(transport.sent.size(), 1U);
  const auto& bid = std::get<Bid>(transport.sent[0].body);
  EXPECT_EQ(bid.estimated_start, clock.utc_now() + 200ms);
  EXPECT_EQ(bid.estimated_finish, clock.utc_now() + 1700ms);
  EXPECT_DOUBLE_EQ(bid.cost, 1.5 * 2.0);
  EXPECT_EQ(bid.queue_length, 3U);
  EXPECT_EQ(backend.last_params, a.params);
  backend.willing = false;
  c.on_announce(announce("b"));
  ASSERT_EQ(transport.sent.size(), 2U);
  EXPECT_EQ(std::get<Refuse>(transport.sent[1].body).reason, "held by the operator");
  EXPECT_EQ(c.stats().declines, 1U);
}

TEST_F(ContractorTest, ABackendGetsTheConfirmedJobAndItsReportEndsIt) {
  RecordingBackend backend;
  ContractorConfig cfg{"M1", {{"OP1", 100ms, 1.0}}};
  cfg.backend = &backend;
  auto c = make(cfg);
  auto a = announce("a");
  a.params = {{"box", 7}};
  c.on_announce(a);
  c.on_manager_message(award("a", 1));
  EXPECT_EQ(backend.started, std::vector<std::string>{"a"});
  EXPECT_EQ(backend.start_params, a.params);
  clock.advance(10s);
  c.tick();  // time alone ends nothing: the backend reports
  EXPECT_TRUE(transport.of_kind<InformDone>().empty());
  EXPECT_EQ(c.next_deadline(), std::nullopt);
  ASSERT_TRUE(c.report("a", true, "3 toffee in slots 4-6", {{"placed", 3}}));
  ASSERT_EQ(transport.of_kind<InformDone>().size(), 1U);
  const auto& done = std::get<InformDone>(transport.sent.back().body);
  EXPECT_EQ(done.result, "3 toffee in slots 4-6");
  EXPECT_EQ(done.results, (std::vector<Param>{{"placed", 3}}));
  EXPECT_EQ(finished, (std::vector<std::pair<std::string, bool>>{{"a", true}}));
  EXPECT_FALSE(c.report("a", true, "again"));  // no such job any more
}

TEST_F(ContractorTest, ABackendsFailedStartOrReportIsAFailureAndACancelAbortsIt) {
  RecordingBackend backend;
  ContractorConfig cfg{"M1", {{"OP1", 100ms, 1.0}}};
  cfg.backend = &backend;
  auto c = make(cfg);
  backend.fail_start = true;
  c.on_announce(announce("a"));
  c.on_manager_message(award("a", 1));
  ASSERT_EQ(transport.of_kind<Failure>().size(), 1U);
  EXPECT_EQ(std::get<Failure>(transport.sent.back().body).reason, "no box at the station");
  backend.fail_start = false;
  c.on_announce(announce("b"));
  c.on_manager_message(award("b", 1));
  ASSERT_TRUE(c.report("b", false, "dispenser empty: " + std::string(200, '.')));
  EXPECT_EQ(std::get<Failure>(transport.sent.back().body).reason.size(), kMaxText);  // fits the wire
  c.on_announce(announce("c"));
  c.on_manager_message(award("c", 1));
  c.on_manager_message(cancel("c", 1));
  ASSERT_EQ(backend.aborted.size(), 1U);
  EXPECT_EQ(backend.aborted[0].first, "c");
  EXPECT_TRUE(c.jobs().empty());
}

// A directed award comes without an announcement: its own parameters are the work's, and a
// backend that would not do the work refuses it (the manager then announces).
TEST_F(ContractorTest, ADirectedAwardAsksTheBackendWithItsOwnParameters) {
  RecordingBackend backend;
  ContractorConfig cfg{"M1", {{"OP1", 100ms, 1.0}}};
  cfg.backend = &backend;
  auto c = make(cfg);
  const std::vector<Param> params{{"box", 7}, {"from", 1}, {"to", 4}};
  c.on_manager_message({"d", "P1", "OP1", "M1", 0, DirectedAward{1, clock.utc_now() + 50ms, params}});
  EXPECT_EQ(backend.last_params, params);
  EXPECT_EQ(transport.of_kind<Confirm>().size(), 1U);
  EXPECT_EQ(backend.started, std::vector<std::string>{"d"});
  EXPECT_EQ(backend.start_params, params);

  backend.willing = false;
  c.on_manager_message({"e", "P1", "OP1", "M1", 0, DirectedAward{1, clock.utc_now() + 50ms, params}});
  EXPECT_EQ(std::get<Refuse>(transport.sent.back().body).reason, "held by the operator");
  EXPECT_EQ(backend.started.size(), 1U);
}

}  // namespace
}  // namespace sf::negotiation
