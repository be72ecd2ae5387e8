// Whole negotiations in memory: products, machines and conveyors on a
// MemoryNetwork driven by a ManualClock. The fault run does 10 000
// negotiations with random latency, reordering between topics, duplicates and
// contractors dying after bidding, after being awarded and while working, and
// checks the invariants: every operation awarded, confirmed and done exactly
// once, never worked by two live contractors at a time, every product finishes.
#include <gtest/gtest.h>

#include <cstdio>
#include <list>
#include <map>
#include <memory>
#include <random>
#include <set>

#include "sf/core/log.hpp"
#include "sf/negotiation/contractor.hpp"
#include "sf/negotiation/manager.hpp"
#include "sf/negotiation/memory_transport.hpp"
#include "sf/negotiation/product.hpp"
#include "sf/negotiation/route.hpp"

namespace sf::negotiation {
namespace {

using namespace std::chrono_literals;

struct Audit {
  std::map<std::string, std::set<std::string>> working;  // conversation → contractors with a live job
  std::map<std::string, int> finished_ok;                // conversation → INFORM-DONE sent
  std::map<std::string, std::set<std::string>> workers;  // conversation → every contractor that started it
  std::set<std::string> dead;
  int overlaps = 0;
  int awards_printed = 0;
};

struct Machine {
  std::string name;
  MemoryContractorEndpoint* endpoint = nullptr;
  std::optional<Contractor> contractor;
};

struct Line {
  std::string name;
  MemoryManagerEndpoint* endpoint = nullptr;
  std::unique_ptr<Manager> manager;
  std::unique_ptr<RoutePlanner> planner;
  std::list<Product> products;
};

class Simulation {
 public:
  explicit Simulation(MemoryNetworkOptions net_options) : net_(clock_, net_options) {}

  Machine& add_machine(const std::string& name, std::vector<std::string> ops, ContractorEvents extra = {}) {
    auto& m = machines_.emplace_back(std::make_unique<Machine>());
    m->name = name;
    m->endpoint = &net_.add_contractor(name, ops);
    ContractorConfig cfg{name, {}};
    for (const auto& op : ops) {
      cfg.skills.push_back({op, 20ms, 1.0});
    }
    cfg.capacity = 8;
    cfg.jitter = 10ms;
    cfg.seed = std::hash<std::string>{}(name);
    ContractorEvents ev = std::move(extra);
    ev.on_work_started = [this, name](const Job& j) { started(name, j); };
    ev.on_work_finished = [this, name](const Job& j, bool ok) { ended(name, j, ok); };
    ev.on_work_aborted = [this, name](const Job& j, const std::string&) { ended(name, j, false); };
    auto c = Contractor::create(*m->endpoint, clock_, cfg, std::move(ev));
    EXPECT_TRUE(c.ok());
    m->contractor.emplace(std::move(*c));
    m->endpoint->bind(*m->contractor);
    return *m;
  }

  void add_conveyor(const std::string& name, const std::string& from, const std::string& to,
                    std::chrono::nanoseconds transit) {
    auto& ep = net_.add_conveyor(name);
    auto c = Conveyor::create(ep, clock_, {name, from, to, transit});
    ASSERT_TRUE(c.ok());
    conveyors_.push_back(std::make_unique<Conveyor>(std::move(*c)));
    ep.bind(*conveyors_.back());
  }

  Line& add_line(const std::string& name, ManagerConfig mc, bool route) {
    auto& l = lines_.emplace_back(std::make_unique<Line>());
    l->name = name;
    l->endpoint = &net_.add_manager();
    l->manager = std::make_unique<Manager>(*l->endpoint, clock_, mc, load_balance());
    l->endpoint->bind(static_cast<ManagerInbox&>(*l->manager));
    if (route) {
      l->planner = std::make_unique<RoutePlanner>(*l->endpoint, clock_, RouteConfig{50ms, 100ms, 0, 0});
      l->endpoint->bind(static_cast<RouteInbox&>(*l->planner));
    }
    return *l;
  }

  Product& add_product(Line& line, ProductPlan plan) {
    ProductEvents ev;
    ev.on_award = [this](const std::string&, const Conversation&) { ++audit.awards_printed; };
    ev.on_finished = [this](const std::string& p, bool ok, const std::string& why) {
      if (ok) {
        ++finished_ok_;
      } else {
        failures_.push_back(p + ": " + why);
      }
    };
    auto& p = line.products.emplace_back(*line.manager, line.planner.get(), std::move(plan), std::move(ev));
    return p;
  }

  void kill(const std::string& name) {
    audit.dead.insert(name);
    net_.kill(name);
    for (auto& [conv, set] : audit.working) {
      set.erase(name);
    }
  }

  // Runs until every product finished or nothing is left to happen.
  void run(std::chrono::nanoseconds limit) {
    const auto end = clock_.now() + limit;
    while (clock_.now() < end) {
      net_.deliver();
      for (auto& l : lines_) {
        l->manager->tick();
        if (l->planner) {
          l->planner->tick();
        }
      }
      for (auto& m : machines_) {
        if (m->endpoint->alive()) {
          m->contractor->tick();
        }
      }
      if (net_.in_flight() == 0 && all_finished()) {
        return;
      }
      auto next = next_event();
      if (!next) {
        return;
      }
      if (*next > clock_.now()) {
        clock_.set(*next);
      }
    }
  }

  [[nodiscard]] bool all_finished() const {
    for (const auto& l : lines_) {
      for (const auto& p : l->products) {
        if (!p.finished()) {
          return false;
        }
      }
    }
    return true;
  }

  std::optional<Clock::time_point> next_event() const {
    std::optional<Clock::time_point> next = net_.next_delivery();
    auto consider = [&](std::optional<Clock::time_point> t) {
      if (t && (!next || *t < *next)) {
        next = t;
      }
    };
    for (const auto& l : lines_) {
      consider(l->manager->next_deadline());
      if (l->planner) {
        consider(l->planner->next_deadline());
      }
    }
    for (const auto& m : machines_) {
      if (m->endpoint->alive()) {
        consider(m->contractor->next_deadline());
      }
    }
    return next;
  }

  ManualClock& clock() { return clock_; }
  MemoryNetwork& network() { return net_; }
  int finished_ok() const { return finished_ok_; }
  const std::vector<std::string>& failures() const { return failures_; }
  std::vector<std::unique_ptr<Line>>& lines() { return lines_; }

  Audit audit;

 private:
  void started(const std::string& who, const Job& j) {
    auto& set = audit.working[j.conversation];
    if (!set.empty()) {
      ++audit.overlaps;
      ADD_FAILURE() << j.conversation << " started by " << who << " while " << *set.begin() << " works it";
    }
    set.insert(who);
    audit.workers[j.conversation].insert(who);
  }
  void ended(const std::string& who, const Job& j, bool ok) {
    audit.working[j.conversation].erase(who);
    if (ok) {
      ++audit.finished_ok[j.conversation];
    }
  }

  ManualClock clock_;
  MemoryNetwork net_;
  std::vector<std::unique_ptr<Machine>> machines_;
  std::vector<std::unique_ptr<Conveyor>> conveyors_;
  std::vector<std::unique_ptr<Line>> lines_;
  int finished_ok_ = 0;
  std::vector<std::string> failures_;
};

ManagerConfig quick_manager() {
  ManagerConfig mc;
  mc.bid_window = 50ms;
  mc.confirm_window = 30ms;
  mc.confirm_grace = 20ms;
  mc.reannounce_delay = 20ms;
  mc.max_rounds = 0;
  return mc;
}

TEST(Simulation, ProductsGetEveryOperationAndRoutesBetweenTheRightMachines) {
  Simulation sim{{1ms, 0ms, true, 0.0, 200ms, 7}};
  sim.add_machine("M1", {"OP1"});
  sim.add_machine("M2", {"OP1", "OP2"});
  sim.add_machine("M3", {"OP2", "OP3"});
  // Input → M1/M2 → M3 → Output, and M1 → M2.
  sim.add_conveyor("C1", "Input", "M1", 1s);
  sim.add_conveyor("C2", "Input", "M2", 3s);
  sim.add_conveyor("C3", "M1", "M2", 1s);
  sim.add_conveyor("C4", "M1", "M3", 2s);
  sim.add_conveyor("C5", "M2", "M3", 1s);
  auto& line = sim.add_line("L", quick_manager(), true);
  std::vector<Product*> products;
  for (int i = 0; i < 3; ++i) {
    products.push_back(
        &sim.add_product(line, {"P" + std::to_string(i), {"OP1", "OP2", "OP3"}, "Input", true, {}}));
  }
  for (auto* p : products) {
    ASSERT_TRUE(p->start().ok());
  }
  sim.run(60s);
  EXPECT_TRUE(sim.failures().empty()) << sim.failures().front();
  ASSERT_EQ(sim.finished_ok(), 3);
  for (auto* p : products) {
    ASSERT_EQ(p->steps().size(), 3U);
    std::string at = "Input";
    for (const auto& step : p->steps()) {
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
    EXPECT_EQ(p->steps()[2].contractor, "M3");  // only M3 does OP3
    EXPECT_EQ(p->location(), "M3");
  }
  for (const auto& [conv, n] : sim.audit.finished_ok) {
    EXPECT_EQ(n, 1) << conv;
  }
  EXPECT_EQ(sim.audit.finished_ok.size(), 9U);
  EXPECT_EQ(sim.audit.awards_printed, 9);
}

TEST(Simulation, ProductWithAnOperationNobodyOffersFails) {
  Simulation sim{{1ms, 0ms, true, 0.0, 200ms, 7}};
  sim.add_machine("M1", {"OP1"});
  auto mc = quick_manager();
  mc.max_rounds = 3;
  auto& line = sim.add_line("L", mc, false);
  auto& p = sim.add_product(line, {"P", {"OP1", "OP9"}, "Input", false, {}});
  ASSERT_TRUE(p.start().ok());
  sim.run(60s);
  ASSERT_TRUE(p.finished());
  EXPECT_FALSE(p.ok());
  EXPECT_NE(p.failure().find("OP9"), std::string::npos);
  EXPECT_EQ(p.steps().size(), 1U);
}

TEST(Simulation, DirectedAwardSkipsTheCall) {
  Simulation sim{{1ms, 0ms, true, 0.0, 200ms, 7}};
  sim.add_machine("M1", {"OP1"});
  sim.add_machine("M2", {"OP1"});
  auto& line = sim.add_line("L", quick_manager(), false);
  auto& p = sim.add_product(line, {"P", {"OP1"}, "Input", false, {{"OP1", "M2"}}});
  ASSERT_TRUE(p.start().ok());
  sim.run(10s);
  ASSERT_TRUE(p.ok());
  EXPECT_EQ(p.steps()[0].contractor, "M2");
  EXPECT_EQ(p.steps()[0].round, 0U);  // no announcement round was needed
}

TEST(Simulation, TenThousandNegotiationsSurviveFaults) {
  ASSERT_TRUE(log::set_level("warn").ok());  // thousands of expected "ignored" lines otherwise
  constexpr int kProducts = 2500;
  const std::vector<std::string> ops{"OP1", "OP2", "OP3", "OP4"};
  // Latency below the confirm grace: a CONFIRM sent in time always counts.
  Simulation sim{{1ms, 8ms, true, 0.02, 150ms, 11}};
  std::mt19937_64 rng{2024};
  int spawned = 0;
  std::vector<std::string> to_kill;
  auto fault_hooks = [&](const std::string& name) {
    ContractorEvents ev;
    ev.on_bid = [&, name](const Announce&) {
      if (std::uniform_real_distribution<double>{0, 1}(rng) < 0.0015) {
        to_kill.push_back(name);
      }
    };
    ev.on_awarded = [&, name](const ManagerMessage&) {
      if (std::uniform_real_distribution<double>{0, 1}(rng) < 0.003) {
        to_kill.push_back(name);
      }
    };
    ev.on_confirmed = [&, name](const Job&) {
      if (std::uniform_real_distribution<double>{0, 1}(rng) < 0.002) {
        to_kill.push_back(name);
      }
    };
    return ev;
  };
  std::map<std::string, std::vector<std::string>> skills;
  auto spawn = [&](std::vector<std::string> supported) {
    const auto name = "M" + std::to_string(++spawned);
    skills[name] = supported;
    sim.add_machine(name, std::move(supported), fault_hooks(name));
  };
  for (int i = 0; i < 12; ++i) {
    spawn({ops[static_cast<std::size_t>(i) % 4], ops[static_cast<std::size_t>(i + 1) % 4]});
  }
  for (int l = 0; l < 10; ++l) {
    auto& line = sim.add_line("L" + std::to_string(l), quick_manager(), false);
    for (int p = 0; p < kProducts / 10; ++p) {
      sim.add_product(line, {fmt::format("P{}_{}", l, p), ops, "Input", false, {}});
    }
  }
  // Products start in waves so queues stay bounded.
  std::vector<Product*> all;
  for (auto& line : sim.lines()) {
    for (auto& p : line->products) {
      all.push_back(&p);
    }
  }
  std::size_t next = 0;
  int kills = 0;
  while (next < all.size() || !sim.all_finished()) {
    for (std::size_t n = 0; n < 60 && next < all.size(); ++n) {
      ASSERT_TRUE(all[next++]->start().ok());
    }
    sim.run(500ms);
    // Killed processes are replaced by new ones, as an operator would.
    for (const auto& name : to_kill) {
      if (!sim.audit.dead.contains(name)) {
        sim.kill(name);
        ++kills;
        spawn(skills[name]);  // the same kind of machine comes back under a new name
      }
    }
    to_kill.clear();
    ASSERT_LT(sim.clock().now().time_since_epoch(), std::chrono::hours{2})
        << "the simulation does not converge";
  }
  EXPECT_TRUE(sim.failures().empty());
  EXPECT_EQ(sim.finished_ok(), kProducts);
  EXPECT_GE(kills, 10);
  EXPECT_EQ(sim.audit.overlaps, 0);
  std::size_t negotiations = 0;
  for (auto* p : all) {
    ASSERT_EQ(p->steps().size(), ops.size());
    negotiations += p->steps().size();
    for (const auto& step : p->steps()) {
      EXPECT_FALSE(sim.audit.dead.contains(step.contractor) && sim.audit.finished_ok[step.conversation] == 0);
      EXPECT_EQ(sim.audit.finished_ok[step.conversation], 1) << step.conversation;
    }
  }
  EXPECT_EQ(negotiations, 10'000U);
  EXPECT_GT(sim.network().stats().duplicated, 0U);
  std::uint64_t renegotiations = 0;
  for (auto& line : sim.lines()) {
    renegotiations += line->manager->stats().renegotiations;
  }
  EXPECT_GT(renegotiations, 0U);
  std::printf(
      "%zu negotiations, %d contractors killed, %llu renegotiations, %llu duplicates, %.0f s simulated\n",
      negotiations, kills, static_cast<unsigned long long>(renegotiations),
      static_cast<unsigned long long>(sim.network().stats().duplicated),
      std::chrono::duration<double>(sim.clock().now().time_since_epoch()).count());
}

}  // namespace
}  // namespace sf::negotiation
