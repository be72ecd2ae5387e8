#include "sf/negotiation/agents.hpp"

#include <algorithm>

#include <fmt/format.h>

namespace sf::negotiation {

Result<std::unique_ptr<MachineAgent>> MachineAgent::create(const DdsSettings& settings,
                                                           ContractorConfig config, ContractorEvents events,
                                                           dds::Executor& executor, const Clock& clock) {
  std::vector<std::string> ops;
  for (const auto& s : config.skills) {
    ops.push_back(s.operation);
  }
  auto endpoints = MachineEndpoints::create(settings, config.name, ops, executor, clock);
  if (!endpoints) {
    return endpoints.error();
  }
  auto agent = std::unique_ptr<MachineAgent>(new MachineAgent());
  agent->endpoints_ = std::move(*endpoints);
  auto contractor = Contractor::create(*agent->endpoints_, clock, std::move(config), std::move(events));
  if (!contractor) {
    return contractor.error();
  }
  agent->contractor_.emplace(std::move(*contractor));
  agent->endpoints_->bind(*agent->contractor_);
  return agent;
}

Result<std::unique_ptr<ConveyorAgent>> ConveyorAgent::create(const DdsSettings& settings,
                                                             ConveyorConfig config, dds::Executor& executor,
                                                             const Clock& clock) {
  auto endpoints = ConveyorEndpoints::create(settings, config.name, executor);
  if (!endpoints) {
    return endpoints.error();
  }
  auto agent = std::unique_ptr<ConveyorAgent>(new ConveyorAgent());
  agent->endpoints_ = std::move(*endpoints);
  auto conveyor = Conveyor::create(*agent->endpoints_, clock, std::move(config));
  if (!conveyor) {
    return conveyor.error();
  }
  agent->conveyor_.emplace(std::move(*conveyor));
  agent->endpoints_->bind(*agent->conveyor_);
  return agent;
}

Result<std::unique_ptr<ProductAgent>> ProductAgent::create(const DdsSettings& settings,
                                                           ProductAgentConfig config, ProductEvents events,
                                                           dds::Executor& executor, const Clock& clock) {
  if (config.count == 0 || config.operations.empty()) {
    return Error{Errc::invalid_argument,
                 fmt::format("product {} needs operations and a count >= 1", config.name)};
  }
  auto endpoints =
      ProductEndpoints::create(settings, config.name, config.operations, executor, clock, config.route);
  if (!endpoints) {
    return endpoints.error();
  }
  auto agent = std::unique_ptr<ProductAgent>(new ProductAgent());
  agent->clock_ = &clock;
  agent->endpoints_ = std::move(*endpoints);
  agent->manager_ = std::make_unique<Manager>(*agent->endpoints_, clock, config.manager, config.policy);
  agent->endpoints_->bind(static_cast<ManagerInbox&>(*agent->manager_));
  if (config.route) {
    agent->planner_ = std::make_unique<RoutePlanner>(*agent->endpoints_, clock, config.routing);
    agent->endpoints_->bind(static_cast<RouteInbox&>(*agent->planner_));
  }
  for (std::size_t i = 1; i <= config.count; ++i) {
    ProductPlan plan{config.count == 1 ? config.name : fmt::format("{}-{}", config.name, i),
                     config.operations,
                     config.start,
                     config.route,
                     config.directed,
                     config.params,
                     config.carry};
    SF_TRY(validate_name("product", plan.name));
    agent->products_.emplace_back(*agent->manager_, agent->planner_.get(), std::move(plan), events);
  }
  agent->next_ = agent->products_.begin();
  agent->created_at_ = clock.now();
  agent->peers_changed_at_ = agent->created_at_;
  agent->config_ = std::move(config);
  return agent;
}

bool ProductAgent::discovered() {
  bool everyone = !config_.route || endpoints_->conveyors() > 0;
  std::size_t peers = config_.route ? endpoints_->conveyors() : 0;
  for (const auto& op : config_.operations) {
    const auto n = endpoints_->contractors(op);
    everyone = everyone && n > 0;
    peers += n;
  }
  const auto now = clock_->now();
  if (peers != peers_) {
    peers_ = peers;
    peers_changed_at_ = now;
  }
  return everyone && now - peers_changed_at_ >= config_.discovery_settle;
}

std::size_t ProductAgent::running() const {
  std::size_t n = 0;
  for (auto it = products_.begin(); it != next_; ++it) {
    n += it->finished() ? 0U : 1U;
  }
  return n;
}

std::size_t ProductAgent::parallel_limit() const {
  return config_.parallel == 0 ? products_.size() : config_.parallel;
}

void ProductAgent::start_more() {
  const std::size_t limit = parallel_limit();
  std::size_t running = this->running();
  while (next_ != products_.end() && running < limit) {
    // A product that cannot start (bad name, ...) finishes at once with its error.
    (void)next_->start();
    running += next_->finished() ? 0U : 1U;
    ++next_;
  }
}

void ProductAgent::tick() {
  if (!started_) {
    // Announcing before anyone listens is allowed (TRANSIENT_LOCAL keeps it),
    // but the first bidder would then be the only one heard.
    if (!discovered() && clock_->now() - created_at_ < config_.discovery_timeout) {
      return;
    }
    started_ = true;
  }
  manager_->tick();
  if (planner_) {
    planner_->tick();
  }
  start_more();
  endpoints_->flush_ended();
}

std::optional<Clock::time_point> ProductAgent::next_deadline() const {
  if (!started_) {
    return clock_->now() + std::chrono::milliseconds{10};
  }
  if (next_ != products_.end() && running() < parallel_limit()) {
    return clock_->now();  // a product finished and the next may start: tick() starts it
  }
  auto next = earliest(manager_->next_deadline(), endpoints_->ends_due());
  return planner_ ? earliest(next, planner_->next_deadline()) : next;
}

bool ProductAgent::finished() const {
  return std::all_of(products_.begin(), products_.end(), [](const Product& p) { return p.finished(); });
}

std::size_t ProductAgent::succeeded() const {
  return static_cast<std::size_t>(
      std::count_if(products_.begin(), products_.end(), [](const Product& p) { return p.ok(); }));
}

std::size_t ProductAgent::failed() const {
  return static_cast<std::size_t>(std::count_if(products_.begin(), products_.end(),
                                                [](const Product& p) { return p.finished() && !p.ok(); }));
}

namespace {

// The earliest timer of the agents; `all_finished` when every agent is done.
std::optional<Clock::time_point> next_deadline(const std::vector<Agent*>& agents, bool& all_finished) {
  std::optional<Clock::time_point> next;
  all_finished = !agents.empty();
  for (Agent* a : agents) {
    next = earliest(next, a->next_deadline());
    all_finished = all_finished && a->finished();
  }
  return next;
}

// Inline delivery for the duration of run_agents. A message handled inline
// wakes the loop only when it moved a timer before the loop's wake-up time,
// finished the last agent or made stop() true; the reply it sent needs no
// wake-up.
class InlineDelivery {
 public:
  InlineDelivery(dds::Executor& executor, const std::vector<Agent*>& agents,
                 const std::function<bool()>& stop, bool on)
      : executor_(executor), on_(on) {
    if (!on_) {
      return;
    }
    const auto strand = executor_.hold();
    executor_.set_wake_check([this, &agents, &stop] {
      bool all_finished = false;
      const auto next = next_deadline(agents, all_finished);
      return all_finished || (next && (!sleeps_until_ || *next < *sleeps_until_)) || stop();
    });
    executor_.set_inline(true);
  }
  ~InlineDelivery() {
    if (on_) {
      const auto strand = executor_.hold();
      executor_.set_inline(false);
      executor_.set_wake_check({});
    }
  }
  InlineDelivery(const InlineDelivery&) = delete;
  InlineDelivery& operator=(const InlineDelivery&) = delete;
  // Under the strand.
  void sleeps_until(std::optional<Clock::time_point> t) { sleeps_until_ = t; }

 private:
  dds::Executor& executor_;
  bool on_;
  std::optional<Clock::time_point> sleeps_until_;
};

}  // namespace

void run_agents(dds::Executor& executor, const Clock& clock, const std::vector<Agent*>& agents,
                const std::function<bool()>& stop, RunOptions options) {
  constexpr std::chrono::nanoseconds kMaxWait = std::chrono::milliseconds{100};
  InlineDelivery delivery{executor, agents, stop, options.inline_delivery};
  while (true) {
    bool all_finished = false;
    bool stopping = false;
    std::optional<Clock::time_point> next;
    {
      const auto strand = executor.hold();
      if (stop()) {
        return;
      }
      executor.run_pending();
      for (Agent* a : agents) {
        a->tick();
      }
      next = next_deadline(agents, all_finished);
      delivery.sleeps_until(next);
      // What ran here may have made stop() true; nothing would wake the sleep below for it.
      stopping = stop();
    }
    if (all_finished || stopping) {
      return;
    }
    if (executor.pending() > 0) {
      continue;
    }
    auto wait = kMaxWait;
    if (next) {
      wait = std::clamp(std::chrono::duration_cast<std::chrono::nanoseconds>(*next - clock.now()),
                        std::chrono::nanoseconds{0}, kMaxWait);
    }
    if (wait.count() > 0) {
      executor.wait_for(wait);
    }
  }
}

}  // namespace sf::negotiation
