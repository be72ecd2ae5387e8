// CentralDispatcher: the scheduling benchmark's baseline for the Contract Net
// (docs/performance.md, "Factory"). One component that knows every machine
// and assigns greedily: for each operation a product asks for, it queries
// every capable controller's estimate() directly and submit()s the job to the
// one that would finish it first (then the shorter job, then the name, the
// ranking of negotiation::earliest_finish()); routes are the shortest by
// transit time over the segments the conveyors offer now, and each hop is
// submitted straight to its conveyor's controller. No messages, no bid
// windows: only the decision mechanism differs from the factory's, the
// products (OrderAgent), controllers, plant and belt discipline are the same.
//
// Decisions and job ends are handed to the products from tick(), as a manager
// hands them its conversations' events, so a product's callbacks never run
// inside a controller's poll(). Single-threaded, like the simulation.
#pragma once

#include <chrono>
#include <cstdint>
#include <deque>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include "sf/core/clock.hpp"
#include "sf/factory/gateway.hpp"
#include "sf/factory/order_agent.hpp"

namespace sf::simulation {

struct DispatcherOptions {
  // When no machine would take an operation: asked again after this, at most max_rounds times
  // (the manager's reannounce delay and rounds).
  std::chrono::nanoseconds retry_delay{std::chrono::milliseconds{200}};
  std::uint32_t max_rounds = 10;
};

struct DispatcherStats {
  std::uint64_t assigned = 0;   // jobs submitted to a machine
  std::uint64_t estimates = 0;  // estimate() calls
  std::uint64_t routes = 0;
  std::uint64_t failed = 0;  // operations no machine took
};

class CentralDispatcher final : public factory::ProductDecisions {
 public:
  explicit CentralDispatcher(const Clock& clock, DispatcherOptions options = {});
  CentralDispatcher(const CentralDispatcher&) = delete;
  CentralDispatcher& operator=(const CentralDispatcher&) = delete;

  // A machine to assign work to (it must outlive the dispatcher; its on_job_end is taken over).
  // A conveyor comes with its offer: the segments it serves now, for routes.
  void add(factory::MachineController& machine, std::function<factory::ConveyorOffer()> offer = {});

  Result<std::string> negotiate(negotiation::OperationRequest request,
                                negotiation::ConversationEvents events) override;
  Result<std::string> plan(const std::string& product, const std::string& from, const std::string& to,
                           negotiation::RouteCallback done) override;

  // Decides what was asked since the last tick, hands out the jobs that ended.
  void tick();
  [[nodiscard]] const DispatcherStats& stats() const { return stats_; }

 private:
  struct Machine {
    factory::MachineController* controller = nullptr;
    std::vector<std::string> operations;
    std::function<factory::ConveyorOffer()> offer;
  };
  struct RouteAsk {
    std::string from;
    std::string to;
    negotiation::RouteCallback done;
  };

  void decide(const std::string& id);
  // The machine that would finish `c`'s operation first, or empty (`why_not`: the last refusal).
  std::string earliest_finish(const negotiation::Conversation& c, const std::string& directed_to,
                              std::string& why_not);
  void on_job_end(const factory::JobOutcome& outcome);
  void route(RouteAsk& ask);

  const Clock* clock_;
  DispatcherOptions options_;
  std::map<std::string, Machine> machines_;  // by name: candidates are tried in name order
  std::map<std::string, negotiation::Conversation> jobs_;
  std::map<std::string, std::string> directed_;        // conversation → conveyor
  std::multimap<Clock::time_point, std::string> due_;  // conversations to decide
  std::deque<factory::JobOutcome> ended_;              // from the controllers' polls
  std::deque<RouteAsk> routes_;
  std::uint64_t next_id_ = 0;
  DispatcherStats stats_;
};

}  // namespace sf::simulation
