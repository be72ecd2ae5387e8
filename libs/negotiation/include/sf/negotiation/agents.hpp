// The shop-floor entities of the paper (§IV.B, §VII) as runnable agents over
// DDS: a machine (contractor), a conveyor, and a product process (manager of
// one or more products). Each agent owns its DDS endpoints and its state
// machine; run_agents() drives any number of agents on one thread: it drains
// the executor (where DDS deliveries land) and fires their timers, or lets
// deliveries run inline on Cyclone's threads under the executor's strand.
#pragma once

#include <chrono>
#include <functional>
#include <list>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "sf/core/clock.hpp"
#include "sf/core/result.hpp"
#include "sf/dds/executor.hpp"
#include "sf/negotiation/contractor.hpp"
#include "sf/negotiation/dds_transport.hpp"
#include "sf/negotiation/manager.hpp"
#include "sf/negotiation/product.hpp"
#include "sf/negotiation/route.hpp"

namespace sf::negotiation {

class Agent {
 public:
  virtual ~Agent() = default;
  virtual void tick() = 0;
  [[nodiscard]] virtual std::optional<Clock::time_point> next_deadline() const = 0;
  [[nodiscard]] virtual bool finished() const { return false; }
};

class MachineAgent final : public Agent {
 public:
  static Result<std::unique_ptr<MachineAgent>> create(const DdsSettings& settings, ContractorConfig config,
                                                      ContractorEvents events, dds::Executor& executor,
                                                      const Clock& clock);
  void tick() override {
    contractor_->tick();
    endpoints_->flush_ended();
    endpoints_->assert_liveliness();
  }
  [[nodiscard]] std::optional<Clock::time_point> next_deadline() const override {
    return earliest(contractor_->next_deadline(),
                    earliest(endpoints_->ends_due(), endpoints_->liveliness_due()));
  }
  [[nodiscard]] Contractor& contractor() { return *contractor_; }
  [[nodiscard]] const MachineEndpoints& endpoints() const { return *endpoints_; }

 private:
  std::unique_ptr<MachineEndpoints> endpoints_;
  std::optional<Contractor> contractor_;
};

class ConveyorAgent final : public Agent {
 public:
  static Result<std::unique_ptr<ConveyorAgent>> create(const DdsSettings& settings, ConveyorConfig config,
                                                       dds::Executor& executor, const Clock& clock);
  void tick() override {}
  [[nodiscard]] std::optional<Clock::time_point> next_deadline() const override { return std::nullopt; }
  [[nodiscard]] Conveyor& conveyor() { return *conveyor_; }
  [[nodiscard]] const ConveyorEndpoints& endpoints() const { return *endpoints_; }

 private:
  std::unique_ptr<ConveyorEndpoints> endpoints_;
  std::optional<Conveyor> conveyor_;
};

struct ProductAgentConfig {
  std::string name;
  std::vector<std::string> operations;
  std::size_t count = 1;     // products of this kind; named NAME-1..NAME-K when K > 1
  std::size_t parallel = 0;  // products in progress at once; 0 = all
  std::string start = "Input";
  bool route = true;
  std::map<std::string, std::string> directed;
  std::map<std::string, std::vector<Param>> params;  // see ProductPlan
  std::vector<std::string> carry{"box"};
  ManagerConfig manager;
  RouteConfig routing;
  SelectionPolicy policy = earliest_finish();
  // Before the first announcement, wait (up to discovery_timeout) until every
  // operation has a contractor listening and, when routing, a conveyor, and
  // the number of matched peers has not changed for discovery_settle: bidding
  // closes once every *matched* contractor answered, so a machine discovered
  // late would miss the first calls.
  std::chrono::nanoseconds discovery_timeout{std::chrono::seconds{5}};
  std::chrono::nanoseconds discovery_settle{std::chrono::milliseconds{300}};
};

// One product process: K products of one kind share its two participants
// (so its DDS layout is the paper's for one product) and one manager.
class ProductAgent final : public Agent {
 public:
  static Result<std::unique_ptr<ProductAgent>> create(const DdsSettings& settings, ProductAgentConfig config,
                                                      ProductEvents events, dds::Executor& executor,
                                                      const Clock& clock);
  void tick() override;
  [[nodiscard]] std::optional<Clock::time_point> next_deadline() const override;
  [[nodiscard]] bool finished() const override;

  [[nodiscard]] std::size_t succeeded() const;
  [[nodiscard]] std::size_t failed() const;
  [[nodiscard]] const std::list<Product>& products() const { return products_; }
  [[nodiscard]] const Manager& manager() const { return *manager_; }
  [[nodiscard]] const ProductEndpoints& endpoints() const { return *endpoints_; }

 private:
  [[nodiscard]] bool discovered();
  void start_more();
  [[nodiscard]] std::size_t running() const;
  [[nodiscard]] std::size_t parallel_limit() const;

  ProductAgentConfig config_;
  const Clock* clock_ = nullptr;
  std::unique_ptr<ProductEndpoints> endpoints_;
  std::unique_ptr<Manager> manager_;
  std::unique_ptr<RoutePlanner> planner_;
  std::list<Product> products_;
  std::list<Product>::iterator next_;
  Clock::time_point created_at_{};
  Clock::time_point peers_changed_at_{};
  std::size_t peers_ = 0;
  bool started_ = false;
};

struct RunOptions {
  // Messages are handled on the DDS thread that received them (the executor's
  // inline delivery) instead of waking this thread for each: one thread
  // wake-up less per message. Off again when run_agents returns.
  bool inline_delivery = false;
};

// Runs until stop() is true or every agent that can finish has finished.
// stop() runs under the executor's strand, so it may look at the agents.
void run_agents(dds::Executor& executor, const Clock& clock, const std::vector<Agent*>& agents,
                const std::function<bool()>& stop, RunOptions options = {});

}  // namespace sf::negotiation
