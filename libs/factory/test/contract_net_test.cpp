// A controller behind the Contract Net contractor: its estimates are the bids, awarded work
// becomes its jobs, its job ends become INFORM-DONE / FAILURE.
#include "sf/factory/contract_net.hpp"

#include <gtest/gtest.h>

#include "test_support.hpp"  // libs/negotiation/test: a transport that records what is sent

namespace sf::factory {
namespace {

using namespace std::chrono_literals;

// A controller whose answers the test sets; the real ones are tested against the plant.
class ScriptedController final : public MachineController {
 public:
  [[nodiscard]] const Identification& identification() const override { return id_; }
  [[nodiscard]] std::vector<std::string> operations() const override { return {"load"}; }
  [[nodiscard]] std::optional<Estimate> estimate(const Operation& op, std::string* why_not) const override {
    asked.push_back(op);
    if (!willing) {
      *why_not = "no toffee in its dispensers";
      return std::nullopt;
    }
    return Estimate{1s, 4s, 2};
  }
  Status submit(const std::string& job, const Operation& op) override {
    submitted.emplace_back(job, op);
    return {};
  }
  Status cancel(const std::string& job) override {
    cancelled.push_back(job);
    return {};
  }
  Status command(PackMLCommand /*command*/) override { return {}; }
  Clock::time_point poll(Clock::time_point now) override { return now; }
  [[nodiscard]] ControllerStatus status() const override { return {}; }
  void end(const std::string& job, bool ok, const std::string& detail) { job_ended({job, ok, detail, {}}); }

  bool willing = true;
  mutable std::vector<Operation> asked;
  std::vector<std::pair<std::string, Operation>> submitted;
  std::vector<std::string> cancelled;

 private:
  Identification id_{"toshiba", "legacy-robot", "TOSHIBA", "THL300", "7"};
};

class ContractNetTest : public ::testing::Test {
 protected:
  ContractNetTest() : backend(controller) {
    negotiation::ContractorConfig cfg{"toshiba", backend.skills()};
    cfg.backend = &backend;
    auto c = negotiation::Contractor::create(transport, clock, cfg);
    EXPECT_TRUE(c) << c.error().describe();
    contractor.emplace(std::move(*c));
    backend.bind(*contractor);
  }
  negotiation::Announce announce(const std::string& conv) {
    return {conv,
            "box-1",
            "load",
            1,
            {{"candy", 3}, {"count", 2}, {"box", 1}, {"slot", 4}},
            clock.utc_now() + 100ms};
  }
  negotiation::ManagerMessage award(const std::string& conv) {
    return {conv, "box-1", "load", "toshiba", 1, negotiation::Award{1, clock.utc_now() + 50ms}};
  }

  ManualClock clock;
  negotiation::test::RecordingContractorTransport transport;
  ScriptedController controller;
  ControllerBackend backend;
  std::optional<negotiation::Contractor> contractor;
};

TEST_F(ContractNetTest, TheControllersEstimateIsTheBid) {
  contractor->on_announce(announce("c1"));
  ASSERT_EQ(controller.asked.size(), 1U);
  EXPECT_EQ(controller.asked[0].type, "load");
  EXPECT_EQ(controller.asked[0].param("candy"), 3.0);
  EXPECT_EQ(controller.asked[0].param("slot"), 4.0);
  const auto& bid = std::get<negotiation::Bid>(transport.sent.at(0).body);
  EXPECT_EQ(bid.estimated_start, clock.utc_now() + 1s);
  EXPECT_EQ(bid.estimated_finish, clock.utc_now() + 5s);
  EXPECT_EQ(bid.queue_length, 2U);
  controller.willing = false;
  contractor->on_announce(announce("c2"));
  EXPECT_EQ(std::get<negotiation::Refuse>(transport.sent.at(1).body).reason, "no toffee in its dispensers");
}

TEST_F(ContractNetTest, AwardedWorkIsAJobAndItsEndTheReport) {
  contractor->on_announce(announce("c1"));
  contractor->on_manager_message(award("c1"));
  ASSERT_EQ(controller.submitted.size(), 1U);
  EXPECT_EQ(controller.submitted[0].first, "c1#1");
  EXPECT_EQ(controller.submitted[0].second.param("box"), 1.0);
  controller.end("c1#1", true, "2 toffee in slots 4-5");
  EXPECT_EQ(std::get<negotiation::InformDone>(transport.sent.back().body).result, "2 toffee in slots 4-5");
  contractor->on_announce(announce("c2"));
  contractor->on_manager_message(award("c2"));
  controller.end("c2#1", false, "dispenser empty");
  EXPECT_EQ(std::get<negotiation::Failure>(transport.sent.back().body).reason, "dispenser empty");
  contractor->on_announce(announce("c3"));
  contractor->on_manager_message(award("c3"));
  contractor->on_manager_message({"c3", "box-1", "load", "toshiba", 1, negotiation::Cancel{1, "lapsed"}});
  EXPECT_EQ(controller.cancelled, std::vector<std::string>{"c3#1"});
}

TEST_F(ContractNetTest, AReAwardOfTheSameConversationIsAJobOfItsOwn) {
  // Award 1 is withdrawn while the controller still winds its job down; the renegotiation
  // awards this machine again (round 2, award 2).
  contractor->on_announce(announce("c4"));
  contractor->on_manager_message(award("c4"));
  contractor->on_manager_message(
      {"c4", "box-1", "load", "toshiba", 1, negotiation::Cancel{1, "contractor lost"}});
  auto again = announce("c4");
  again.round = 2;
  contractor->on_announce(again);
  contractor->on_manager_message(
      {"c4", "box-1", "load", "toshiba", 2, negotiation::Award{2, clock.utc_now() + 50ms}});
  ASSERT_EQ(controller.submitted.size(), 2U);
  EXPECT_EQ(controller.submitted[1].first, "c4#2");
  const auto sent = transport.sent.size();
  controller.end("c4#1", false, "cancelled");  // the old job's end: not the new award's
  EXPECT_EQ(transport.sent.size(), sent);
  controller.end("c4#2", true, "2 toffee in slots 4-5");
  const auto& done = std::get<negotiation::InformDone>(transport.sent.back().body);
  EXPECT_EQ(done.award_id, 2U);
}

TEST(JobId, NamesTheConversationAndTheAward) {
  negotiation::Job job;
  job.conversation = "it-7.1/load/aff3b6.12";
  job.award_id = 3;
  EXPECT_EQ(job_id(job), "it-7.1/load/aff3b6.12#3");
  EXPECT_EQ(parse_job_id(job_id(job)), (std::pair<std::string, std::uint32_t>{job.conversation, 3}));
  for (const char* bad : {"j1", "#3", "c#", "c#x", "c#3x", "c#99999999999"}) {
    EXPECT_FALSE(parse_job_id(bad)) << bad;
  }
}

}  // namespace
}  // namespace sf::factory
