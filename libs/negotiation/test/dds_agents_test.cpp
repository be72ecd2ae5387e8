// The agents over real DDS (loopback, a partition private to this process):
// the entity layout of the paper, whole negotiations with routes, and a
// machine that dies after confirming.
#include "sf/negotiation/agents.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <map>

#include "sf/dds/introspection.hpp"

namespace sf::negotiation {
namespace {

using namespace std::chrono_literals;

DdsSettings settings() {
  DdsSettings s;
  s.machining_domain = 78;
  s.conveying_domain = 79;
  s.partition = fmt::format("sf-cnp-test-{}-{}", ::getpid(),
                            ::testing::UnitTest::GetInstance()->current_test_info()->name());
  s.liveliness_lease = 1s;
  return s;
}

ContractorConfig machine(const std::string& name, std::vector<std::string> ops,
                         std::chrono::milliseconds work = 20ms, double speed = 1.0) {
  ContractorConfig c{name, {}};
  for (auto& op : ops) {
    c.skills.push_back({op, work, 1.0});
  }
  c.speed = speed;
  return c;
}

ProductAgentConfig product(const std::string& name, std::vector<std::string> ops, bool route) {
  ProductAgentConfig c;
  c.name = name;
  c.operations = std::move(ops);
  c.route = route;
  c.manager.bid_window = 1s;
  c.manager.confirm_window = 1s;
  c.manager.max_rounds = 0;
  c.routing.collect_window = 1s;
  return c;
}

std::vector<std::string> sorted(std::vector<std::string> v) {
  std::sort(v.begin(), v.end());
  return v;
}

TEST(DdsLayout, EveryEntityHasThePapersReadersAndWriters) {
  const auto s = settings();
  dds::Executor ex;
  auto& clock = SteadyClock::instance();
  auto p = ProductAgent::create(s, product("P1", {"OP1", "OP2", "OP3"}, true), {}, ex, clock);
  ASSERT_TRUE(p.ok()) << p.error().describe();
  auto m = MachineAgent::create(s, machine("M1", {"OP1", "OP2"}), {}, ex, clock);
  ASSERT_TRUE(m.ok()) << m.error().describe();
  auto c = ConveyorAgent::create(s, {"C1", "Input", "M1", 1s}, ex, clock);
  ASSERT_TRUE(c.ok()) << c.error().describe();

  // Product, MachiningDomain: per required operation a writer on ANNOUNCE and
  // AWARD and a reader on BID.
  auto pm = dds::inspect((*p)->endpoints().machining());
  ASSERT_TRUE(pm.ok());
  EXPECT_EQ(pm->domain, s.machining_domain);
  EXPECT_EQ(sorted(pm->writer_topics()),
            (std::vector<std::string>{"OP1_ANNOUNCE", "OP1_AWARD", "OP2_ANNOUNCE", "OP2_AWARD",
                                      "OP3_ANNOUNCE", "OP3_AWARD"}));
  EXPECT_EQ(pm->reader_topics(), (std::vector<std::string>{"OP1_BID", "OP2_BID", "OP3_BID"}));
  // Product, ConveyingDomain: one writer REQUEST, one reader INFORM.
  ASSERT_NE((*p)->endpoints().conveying(), nullptr);
  auto pc = dds::inspect(*(*p)->endpoints().conveying());
  ASSERT_TRUE(pc.ok());
  EXPECT_EQ(pc->domain, s.conveying_domain);
  EXPECT_EQ(pc->writer_topics(), std::vector<std::string>{"REQUEST"});
  EXPECT_EQ(pc->reader_topics(), std::vector<std::string>{"INFORM"});
  // Machine: per supported operation a reader on ANNOUNCE and AWARD, a writer on BID.
  auto mm = dds::inspect((*m)->endpoints().participant());
  ASSERT_TRUE(mm.ok());
  EXPECT_EQ(mm->domain, s.machining_domain);
  EXPECT_EQ(mm->reader_topics(),
            (std::vector<std::string>{"OP1_ANNOUNCE", "OP1_AWARD", "OP2_ANNOUNCE", "OP2_AWARD"}));
  EXPECT_EQ(mm->writer_topics(), (std::vector<std::string>{"OP1_BID", "OP2_BID"}));
  // Conveyor: exactly one reader (REQUEST) and one writer (INFORM).
  auto cc = dds::inspect((*c)->endpoints().participant());
  ASSERT_TRUE(cc.ok());
  EXPECT_EQ(cc->domain, s.conveying_domain);
  EXPECT_EQ(cc->reader_topics(), std::vector<std::string>{"REQUEST"});
  EXPECT_EQ(cc->writer_topics(), std::vector<std::string>{"INFORM"});
  EXPECT_EQ(cc->readers[0].type, "sf_cnp::TransportRequest");

  // The same layout as other participants see it, through the built-in topics.
  auto seen = dds::discover((*m)->endpoints().participant(), clock, 1s, s.partition);
  ASSERT_TRUE(seen.ok()) << seen.error().describe();
  std::map<std::string, dds::EntityLayout> by_name;
  for (auto& l : *seen) {
    by_name[l.participant] = l;
  }
  ASSERT_TRUE(by_name.contains("product/P1"));
  ASSERT_TRUE(by_name.contains("machine/M1"));
  EXPECT_FALSE(by_name.contains("conveyor/C1"));  // another domain
  EXPECT_EQ(sorted(by_name["product/P1"].writer_topics()), sorted(pm->writer_topics()));
  EXPECT_EQ(by_name["machine/M1"].reader_topics(), mm->reader_topics());
}

struct Recorder {
  std::map<std::string, std::vector<std::string>> awards;  // conversation → confirmed contractors
  std::map<std::string, int> started;                      // conversation → jobs started
  std::map<std::string, int> done;                         // conversation → INFORM-DONE sent
  std::vector<std::string> failures;

  ProductEvents product_events() {
    ProductEvents ev;
    ev.on_award = [this](const std::string&, const Conversation& c) { awards[c.id].push_back(c.contractor); };
    ev.on_finished = [this](const std::string& p, bool ok, const std::string& why) {
      if (!ok) {
        failures.push_back(p + ": " + why);
      }
    };
    return ev;
  }
  ContractorEvents machine_events() {
    ContractorEvents ev;
    ev.on_work_started = [this](const Job& j) { ++started[j.conversation]; };
    ev.on_work_finished = [this](const Job& j, bool ok) { done[j.conversation] += ok ? 1 : 0; };
    return ev;
  }
};

// Every negotiation test runs with queued and with inline delivery. In one
// process Cyclone delivers a write to a local reader on the writing thread,
// which holds the strand, so most messages are queued either way; the inline
// variant checks the strand and wake-up bookkeeping of run_agents with
// Cyclone's own threads (discovery, liveliness) posting. Inline handling of
// messages from other processes is what the cnp_* integration tests run (the
// agent CLI's default).
class DdsNegotiation : public ::testing::TestWithParam<bool> {
 protected:
  bool run_until(dds::Executor& ex, const std::vector<Agent*>& agents, const std::function<bool()>& done,
                 std::chrono::seconds bound = 60s) {
    const auto end = SteadyClock::instance().now() + bound;
    run_agents(
        ex, SteadyClock::instance(), agents, [&] { return done() || SteadyClock::instance().now() > end; },
        RunOptions{GetParam()});
    return done();
  }
};

INSTANTIATE_TEST_SUITE_P(Delivery, DdsNegotiation, ::testing::Bool(),
                         [](const auto& p) { return p.param ? "Inline" : "Queued"; });

TEST_P(DdsNegotiation, ProductsGetEachOperationOnceWithRoutesBetweenTheRightMachines) {
  const auto s = settings();
  dds::Executor ex;
  auto& clock = SteadyClock::instance();
  Recorder rec;
  std::vector<std::unique_ptr<Agent>> agents;
  for (auto [name, ops] : std::vector<std::pair<std::string, std::vector<std::string>>>{
           {"M1", {"OP1"}}, {"M2", {"OP1", "OP2"}}, {"M3", {"OP2", "OP3"}}}) {
    auto m = MachineAgent::create(s, machine(name, ops), rec.machine_events(), ex, clock);
    ASSERT_TRUE(m.ok()) << m.error().describe();
    agents.push_back(std::move(*m));
  }
  for (auto [name, from, to] :
       std::vector<std::tuple<std::string, std::string, std::string>>{{"C1", "Input", "M1"},
                                                                      {"C2", "Input", "M2"},
                                                                      {"C3", "M1", "M2"},
                                                                      {"C4", "M1", "M3"},
                                                                      {"C5", "M2", "M3"}}) {
    auto c = ConveyorAgent::create(s, {name, from, to, 1s}, ex, clock);
    ASSERT_TRUE(c.ok());
    agents.push_back(std::move(*c));
  }
  std::vector<ProductAgent*> products;
  for (const auto* name : {"PA", "PB"}) {
    auto cfg = product(name, {"OP1", "OP2", "OP3"}, true);
    cfg.count = 2;
    auto p = ProductAgent::create(s, cfg, rec.product_events(), ex, clock);
    ASSERT_TRUE(p.ok()) << p.error().describe();
    products.push_back(p->get());
    agents.push_back(std::move(*p));
  }
  std::vector<Agent*> raw;
  for (auto& a : agents) {
    raw.push_back(a.get());
  }
  ASSERT_TRUE(run_until(ex, raw, [&] {
    return std::all_of(products.begin(), products.end(), [](ProductAgent* p) { return p->finished(); });
  }));
  EXPECT_TRUE(rec.failures.empty()) << rec.failures.front();
  ASSERT_EQ(rec.awards.size(), 12U);  // 4 products x 3 operations
  for (const auto& [conv, who] : rec.awards) {
    EXPECT_EQ(who.size(), 1U) << conv;
    EXPECT_EQ(rec.started[conv], 1) << conv;
    EXPECT_EQ(rec.done[conv], 1) << conv;
  }
  // Ended conversations were disposed: every machine forgets them.
  std::vector<MachineAgent*> machines;
  for (auto& a : agents) {
    if (auto* m = dynamic_cast<MachineAgent*>(a.get())) {
      machines.push_back(m);
    }
  }
  EXPECT_TRUE(run_until(ex, raw, [&] {
    return std::all_of(machines.begin(), machines.end(),
                       [](MachineAgent* m) { return m->contractor().conversations() == 0; });
  }));
  for (auto* p : products) {
    EXPECT_EQ(p->succeeded(), 2U);
    for (const auto& prod : p->products()) {
      std::string at = "Input";
      ASSERT_EQ(prod.steps().size(), 3U);
      for (const auto& step : prod.steps()) {
        ASSERT_TRUE(step.route.has_value());
        EXPECT_EQ(step.route->from, at);
        EXPECT_EQ(step.route->to, step.contractor);
        std::string hop = at;
        for (const auto& seg : step.route->segments) {
          EXPECT_EQ(seg.from, hop);
          hop = seg.to;
        }
        EXPECT_EQ(hop, step.contractor);
        at = step.contractor;
      }
      EXPECT_EQ(prod.steps()[2].contractor, "M3");
    }
  }
}

TEST_P(DdsNegotiation, MachineLostAfterConfirmingIsReplacedByRenegotiation) {
  auto s = settings();
  dds::Executor ex;
  auto& clock = SteadyClock::instance();
  Recorder rec;
  // M1 is faster, so it wins; its job takes long enough to die in the middle.
  auto m1 = MachineAgent::create(s, machine("M1", {"OP1"}, 30s, 2.0), rec.machine_events(), ex, clock);
  auto m2 = MachineAgent::create(s, machine("M2", {"OP1"}, 30s, 1.0), rec.machine_events(), ex, clock);
  ASSERT_TRUE(m1.ok() && m2.ok());
  auto cfg = product("P", {"OP1"}, false);
  auto p = ProductAgent::create(s, cfg, rec.product_events(), ex, clock);
  ASSERT_TRUE(p.ok());
  std::unique_ptr<MachineAgent> first = std::move(*m1);
  std::vector<Agent*> raw{first.get(), m2->get(), p->get()};
  ASSERT_TRUE(run_until(ex, raw, [&] { return !rec.awards.empty(); }));
  ASSERT_EQ(rec.awards.begin()->second, std::vector<std::string>{"M1"});
  // M1's process goes away: its OP1_BID writer is gone, liveliness changes.
  first.reset();
  raw = {m2->get(), p->get()};
  ASSERT_TRUE(run_until(ex, raw, [&] { return rec.awards.begin()->second.size() == 2; }));
  EXPECT_EQ(rec.awards.begin()->second[1], "M2");
  EXPECT_EQ((*p)->manager().stats().renegotiations, 1U);
  const auto* c = (*p)->manager().find(rec.awards.begin()->first);
  ASSERT_NE(c, nullptr);
  EXPECT_EQ(c->contractor, "M2");
  EXPECT_EQ(c->phase, Phase::Working);
}

}  // namespace
}  // namespace sf::negotiation
