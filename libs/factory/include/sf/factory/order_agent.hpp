// OrderAgent: the product agent of one order (paper §IV.B, §VII): the box
// negotiates its own way through the line. Its operations come from the
// order (upload a box of its type, the loads of load_tasks(), download); for
// each one, in order:
//
//   1. negotiate the operation in the MachiningDomain (Contract Net) until a
//      machine has confirmed it;
//   2. only then negotiate the route from where the box is to that machine's
//      station in the ConveyingDomain, and award each conveyor of the route
//      its hop ("transport", one conveyor after the other), so a box never
//      waits for a machine that has not confirmed; a hop onto the next belt
//      waits until that belt is the box's (BeltBlocks);
//   3. the machine begins the job when its tag reader reads the box in place,
//      and its INFORM-DONE ends the step.
//
// If the machine fails or is lost, the manager negotiates the operation again
// and the box is routed to the new machine from where it stands. If the lost
// machine was only cut off and reports the work done after all, the step ends
// with its report: a box already on its way to the new machine stops where its
// transport ends and goes on from there to the next step's machine. A
// conversation that finds no machine at all, or a route or transport that
// fails, is tried again after a delay. The downloader's inspection (weight,
// candies per type) ends the order: it is done when the content equals the
// order; otherwise the box is rejected ("content mismatch") and the attempt
// fails, for the host to make the order again. A box whose order cannot be
// finished (a step failed again and again) is taken off the line as a reject
// by the downloader, so that it does not stand in the way of others. Every step is reported as an
// OrderEvent, the order's lifecycle for the cloud.
//
// Single-threaded, like the Manager and RoutePlanner it runs on (shared with
// the other products of its host).
#pragma once

#include <chrono>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "sf/core/clock.hpp"
#include "sf/factory/order.hpp"
#include "sf/line/layout.hpp"
#include "sf/negotiation/manager.hpp"
#include "sf/negotiation/route.hpp"

namespace sf::factory {

struct OrderAgentOptions {
  int max_per_load = 4;  // candies per robot visit; longer lines are split
  std::chrono::nanoseconds retry_delay{std::chrono::seconds{1}};
  std::uint32_t max_retries = 30;  // per step, then the order fails
};

// The downloader's inspection of a finished box.
struct BoxInspection {
  std::uint16_t box = 0;
  double weight_g = 0.0;
  std::map<std::string, int> counts;  // per candy type, zero counts left out
};

struct OrderEvent {
  Clock::time_point at{};
  std::string order;
  // accepted, started (a box for it begins), awarded, routed, transported, uploaded, loaded,
  // inspected, done, failed, retry, rejected, remade, cancelled, cancel-refused
  std::string what;
  std::string machine;  // the machine or conveyor it concerns
  std::string detail;
  std::optional<BoxInspection> inspection;  // "inspected": what the downloader found
};

using OrderEventSink = std::function<void(const OrderEvent&)>;

// Block control over the belts (as accumulating conveyors and railways do
// it): a box enters a belt only while no other box of the host is on it. A
// conveyor's stoppers hold a box only at stations, so a second box waiting at
// a belt's entry would roll on with the first one's transport and stop at some
// other station; with one box per belt every box is where its product thinks.
// (Boxes of the host only: one order service per line.)
class BeltBlocks {
 public:
  // True when the belt is free or already `holder`'s; it is then `holder`'s.
  bool reserve(const std::string& belt, const std::string& holder);
  void release(const std::string& belt, const std::string& holder);
  void release_all(const std::string& holder);
  [[nodiscard]] std::size_t held() const { return held_.size(); }

 private:
  std::map<std::string, std::string> held_;  // belt → holder
};

// The belt of a place ("conveyor2/scara1" or the entry "conveyor2").
std::string belt_of(const std::string& place);

// Who decides a product's machines and routes. In the factory that is the
// Contract Net (ContractNetDecisions: the host's manager and route planner);
// a benchmark may put a central dispatcher here to compare against it. Both
// answer through the Contract Net's conversation events, so the product's
// steps are the same whoever decides.
class ProductDecisions {
 public:
  virtual ~ProductDecisions() = default;
  // An operation for `request.product` (directed_to: this machine only); its id.
  virtual Result<std::string> negotiate(negotiation::OperationRequest request,
                                        negotiation::ConversationEvents events) = 0;
  // A route from `from` to `to`; `done` is called exactly once.
  virtual Result<std::string> plan(const std::string& product, const std::string& from, const std::string& to,
                                   negotiation::RouteCallback done) = 0;
};

// How products negotiate (the order service's Manager, and the simulation's): a machine whose
// liveliness lease ran out while it worked gets kLostGrace to come back before its work goes to
// another machine. A loaded host misses a lease now and then, and a belt that is already moving
// a box cannot be undone by a second award; a machine that is really gone (killed, cut off) is
// replaced after its lease plus the grace.
inline constexpr std::chrono::seconds kLostGrace{3};
negotiation::ManagerConfig product_manager_config();

// The Contract Net's decisions (paper §IV.B): MachiningDomain conversations and
// ConveyingDomain route requests. Both must outlive it.
class ContractNetDecisions final : public ProductDecisions {
 public:
  ContractNetDecisions(negotiation::Manager& manager, negotiation::RoutePlanner& planner)
      : manager_(&manager), planner_(&planner) {}
  Result<std::string> negotiate(negotiation::OperationRequest request,
                                negotiation::ConversationEvents events) override {
    return manager_->negotiate(std::move(request), std::move(events));
  }
  Result<std::string> plan(const std::string& product, const std::string& from, const std::string& to,
                           negotiation::RouteCallback done) override {
    return planner_->plan(product, from, to, std::move(done));
  }

 private:
  negotiation::Manager* manager_;
  negotiation::RoutePlanner* planner_;
};

// What the products of one host run on: the line's layout (stations, places,
// catalog), who decides their machines and routes, its clock.
struct ProductContext {
  const line::Layout* layout = nullptr;
  ProductDecisions* decisions = nullptr;
  const Clock* clock = nullptr;
  BeltBlocks* belts = nullptr;
};

class OrderAgent : public std::enable_shared_from_this<OrderAgent> {
 public:
  // `product` names the order's product in the Contract Net (unique per attempt).
  static std::shared_ptr<OrderAgent> create(Order order, std::string product, const ProductContext& context,
                                            OrderAgentOptions options, OrderEventSink sink);
  OrderAgent(const OrderAgent&) = delete;
  OrderAgent& operator=(const OrderAgent&) = delete;

  Status start();
  // Runs a retry that is due.
  void tick();

  [[nodiscard]] bool finished() const { return finished_; }
  [[nodiscard]] bool ok() const { return finished_ && failure_.empty(); }
  [[nodiscard]] const std::string& failure() const { return failure_; }
  [[nodiscard]] const Order& order() const { return order_; }
  [[nodiscard]] const std::string& product() const { return product_; }
  [[nodiscard]] std::uint16_t box() const { return box_; }
  [[nodiscard]] const std::string& location() const { return location_; }
  [[nodiscard]] const std::optional<BoxInspection>& inspection() const { return inspection_; }

 private:
  struct StepOp {
    std::string type;
    std::vector<negotiation::Param> params;
  };
  struct Hop {
    std::string conveyor;
    std::string from;
    std::string to;
  };

  OrderAgent(Order order, std::string product, const ProductContext& context, OrderAgentOptions options,
             OrderEventSink sink);

  void begin_step();
  void on_confirmed(const negotiation::Conversation& c);
  void on_work_done(const negotiation::Conversation& c);
  void route_to_machine();
  void on_route(const Result<negotiation::Route>& route);
  void next_transport();
  void retry(std::string why, std::function<void()> again);
  // Runs `then` once `belt` is this product's (at once, or from tick()).
  void with_belt(const std::string& belt, std::function<void()> then);
  void give_up(std::string failure);
  // The box is a reject (a "rejected" event): it leaves the line at the downloader and the
  // attempt fails with `why`.
  void reject(std::string why);
  void finish(std::string failure);
  void emit(std::string what, std::string machine, std::string detail,
            std::optional<BoxInspection> inspection = std::nullopt);
  [[nodiscard]] std::string station_of(const std::string& machine) const;
  [[nodiscard]] std::string verify(const BoxInspection& inspection) const;
  // A callback that reaches this agent while it lives (the manager may outlive it).
  template <typename F>
  auto guarded(F f);

  Order order_;
  std::string product_;
  ProductContext context_;
  const line::Layout* layout_;
  const Clock* clock_;
  OrderAgentOptions options_;
  OrderEventSink sink_;

  std::vector<StepOp> steps_;
  std::size_t step_ = 0;
  std::uint32_t retries_ = 0;
  std::string machine_;  // confirmed for the current step
  std::string target_;   // its station
  bool moving_ = false;  // a route or transport in progress
  std::vector<Hop> hops_;
  std::string location_;
  std::uint16_t box_ = 0;
  std::optional<BoxInspection> inspection_;
  std::optional<Clock::time_point> retry_at_;
  std::function<void()> retry_;
  std::string waiting_for_;  // a belt
  std::function<void()> on_belt_;
  bool finished_ = false;
  std::string failure_;
  std::string rejected_;  // why the box is on its way out as a reject
};

}  // namespace sf::factory
