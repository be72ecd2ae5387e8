// The scheduling benchmark's baseline: the central dispatcher assigns each
// operation to the machine that would finish it first, and the products make
// their orders with it on the real line as they do with the Contract Net.
#include "sf/simulation/central_dispatcher.hpp"

#include <map>
#include <optional>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "sf/simulation/run.hpp"
#include "sf/simulation/simulation.hpp"
#include "simulation_checks.hpp"

namespace sf::simulation {
namespace {

using namespace std::chrono_literals;
namespace checks = testing;

// A machine that estimates what it is told to and records what it was given.
class ScriptedMachine final : public factory::MachineController {
 public:
  ScriptedMachine(std::string name, std::optional<factory::Estimate> estimate)
      : id_{std::move(name), "scripted", {}, {}, {}}, estimate_(estimate) {}
  [[nodiscard]] const factory::Identification& identification() const override { return id_; }
  [[nodiscard]] std::vector<std::string> operations() const override { return {"load"}; }
  [[nodiscard]] std::optional<factory::Estimate> estimate(const factory::Operation& /*op*/,
                                                          std::string* why_not) const override {
    if (!estimate_ && why_not != nullptr) {
      *why_not = "no stock";
    }
    return estimate_;
  }
  Status submit(const std::string& job, const factory::Operation& op) override {
    jobs.emplace_back(job, op);
    return {};
  }
  Status cancel(const std::string& /*job*/) override { return {}; }
  Status command(factory::PackMLCommand /*command*/) override { return {}; }
  Clock::time_point poll(Clock::time_point now) override { return now; }
  [[nodiscard]] factory::ControllerStatus status() const override { return {}; }
  void end(const std::string& job, bool ok) const { job_ended({job, ok, "3 gummy", {{"placed", 3.0}}}); }

  std::vector<std::pair<std::string, factory::Operation>> jobs;

 private:
  factory::Identification id_;
  std::optional<factory::Estimate> estimate_;
};

struct Outcome {
  std::vector<std::string> confirmed;
  std::vector<std::string> done;
  std::vector<std::string> failed;
  negotiation::ConversationEvents events() {
    return {[this](const negotiation::Conversation& c) { confirmed.push_back(c.contractor); },
            [this](const negotiation::Conversation& c) { done.push_back(c.contractor + " " + c.result); },
            [this](const negotiation::Conversation& c) { failed.push_back(c.failure); }};
  }
};

TEST(CentralDispatcher, AssignsTheMachineThatFinishesFirst) {
  ManualClock clock;
  CentralDispatcher dispatcher(clock);
  ScriptedMachine idle_but_slow("a", factory::Estimate{0s, 9s, 0});
  ScriptedMachine busy_but_fast("b", factory::Estimate{3s, 2s, 1});  // finishes at 5 s
  ScriptedMachine out_of_stock("c", std::nullopt);
  for (auto* m : {&idle_but_slow, &busy_but_fast, &out_of_stock}) {
    dispatcher.add(*m);
  }
  Outcome outcome;
  ASSERT_TRUE(dispatcher.negotiate({"p.1", "load", {{"candy", 1}, {"count", 3}}, {}}, outcome.events()));
  EXPECT_TRUE(outcome.confirmed.empty()) << "decisions are handed out from tick()";
  dispatcher.tick();
  ASSERT_EQ(outcome.confirmed, std::vector<std::string>{"b"});
  ASSERT_EQ(busy_but_fast.jobs.size(), 1U);
  EXPECT_TRUE(idle_but_slow.jobs.empty());
  EXPECT_EQ(busy_but_fast.jobs[0].second.params.at("count"), 3.0);

  busy_but_fast.end(busy_but_fast.jobs[0].first, true);
  EXPECT_TRUE(outcome.done.empty());
  dispatcher.tick();
  EXPECT_EQ(outcome.done, std::vector<std::string>{"b 3 gummy"});
  EXPECT_EQ(dispatcher.stats().assigned, 1U);
}

TEST(CentralDispatcher, AFailedJobIsAssignedAgainAndADirectedOneGoesOnlyToItsMachine) {
  ManualClock clock;
  CentralDispatcher dispatcher(clock);
  ScriptedMachine a("a", factory::Estimate{0s, 1s, 0});
  ScriptedMachine b("b", factory::Estimate{0s, 5s, 0});
  dispatcher.add(a);
  dispatcher.add(b);
  Outcome outcome;
  ASSERT_TRUE(dispatcher.negotiate({"p.1", "load", {}, "b"}, outcome.events()));
  dispatcher.tick();
  EXPECT_EQ(outcome.confirmed, std::vector<std::string>{"b"});
  b.end(b.jobs.at(0).first, false);
  dispatcher.tick();  // the failure: assigned again, at once
  dispatcher.tick();
  EXPECT_EQ(outcome.confirmed, (std::vector<std::string>{"b", "b"}));
  EXPECT_TRUE(a.jobs.empty());
  EXPECT_TRUE(outcome.done.empty());
}

TEST(CentralDispatcher, AnOperationNoMachineTakesFailsAfterItsRounds) {
  ManualClock clock;
  DispatcherOptions options;
  options.max_rounds = 3;
  CentralDispatcher dispatcher(clock, options);
  ScriptedMachine empty("a", std::nullopt);
  dispatcher.add(empty);
  Outcome outcome;
  ASSERT_TRUE(dispatcher.negotiate({"p.1", "load", {}, {}}, outcome.events()));
  for (int i = 0; i < 1000 && outcome.failed.empty(); ++i) {
    clock.advance(1ms);
    dispatcher.tick();
  }
  ASSERT_EQ(outcome.failed.size(), 1U);
  EXPECT_NE(outcome.failed[0].find("a: no stock"), std::string::npos) << outcome.failed[0];
  EXPECT_GE(clock.now().time_since_epoch(), 2 * options.retry_delay);
  EXPECT_TRUE(outcome.confirmed.empty());
}

TEST(CentralDispatcher, AnOrderIsMadeOnTheLineWithItsContentAndNoMessages) {
  SimulationOptions options;
  options.decisions = Decisions::central_dispatcher;
  auto sim = checks::make(options);
  ASSERT_TRUE(sim);
  checks::expect_made(*sim, {"bob-1", "small-box", {{"gummy", 2}, {"toffee", 1}, {"lollipop", 1}}});
  EXPECT_EQ(sim->messages(), 0U);
  checks::dump_on_failure(*sim);
}

TEST(CentralDispatcher, ARunReportsTheBottleneckAndTheDecisionsWait) {
  for (const Decisions d : {Decisions::contract_net, Decisions::central_dispatcher}) {
    SimulationOptions options;
    options.decisions = d;
    auto sim = checks::make(options);
    ASSERT_TRUE(sim);
    RunOptions run;
    run.orders = 6;
    const RunReport r = run_orders(*sim, run);
    EXPECT_EQ(r.done, 6U);
    EXPECT_FALSE(r.bottleneck.empty());
    EXPECT_GT(r.utilisation(), 0.0);
    EXPECT_LE(r.utilisation(), 1.0);
    EXPECT_GE(r.bound_boxes_per_hour(), r.boxes_per_hour());
    EXPECT_GT(r.deciding.count(), 0);
    EXPECT_LT(r.deciding, r.on_line);
    checks::dump_on_failure(*sim);
  }
}

}  // namespace
}  // namespace sf::simulation
