// OrderHost: the order service's core (paper §VII), the process products live
// in, apart from the machines. It takes orders (validated against the
// catalog), admits them onto the line as product agents, at most `wip` boxes
// at once, and follows them to the end: an order whose box failed (a content
// mismatch at the inspection, a step that found no machine) is made again
// with a new box, up to max_attempts. All its products share one Contract
// Net manager and one route planner (one endpoint per domain for the host);
// each product is its own party in them (its name in every conversation).
//
// The host keeps the belt blocks of its products (BeltBlocks) unless the
// context brings its own. `wip` bounds the boxes on the line so that the belts cannot fill up: with
// fewer boxes than the shortest cycle of belts has belts, boxes waiting for
// one another cannot close a circle.
#pragma once

#include <array>
#include <chrono>
#include <cstdint>
#include <deque>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "sf/factory/order_agent.hpp"
#include "sf/line/inspection.hpp"

namespace sf::factory {

struct OrderHostOptions {
  std::size_t wip = 3;  // boxes on the line at once; 0: the layout's safe bound
  std::uint32_t max_attempts = 3;
  OrderAgentOptions agent;
};

// cancelled: withdrawn by its consumer before a box was started for it.
enum class OrderState : std::uint8_t { queued, in_work, done, failed, cancelled };
inline constexpr std::size_t kOrderStates = 5;
std::string_view to_string(OrderState s);

struct OrderRecord {
  Order order;
  OrderState state = OrderState::queued;
  std::uint32_t attempts = 0;
  Clock::time_point accepted{};
  Clock::time_point finished{};
  std::vector<std::uint16_t> boxes;  // one per attempt that got a box
  std::string failure;               // of the last attempt
  std::optional<BoxInspection> inspection;
};

class OrderHost {
 public:
  OrderHost(const ProductContext& context, OrderHostOptions options = {}, OrderEventSink sink = {});

  // Accepts a valid order with an id not seen before; errors say why not.
  Status submit(Order order);
  // Withdraws a queued order (event "cancelled"); an order already in work, made or failed
  // stays as it is (Errc::state says which), an unknown one is Errc::not_found.
  Status cancel(const std::string& id);
  // Admits queued orders, runs due retries, follows finished products.
  void tick();

  // How many of the accepted orders are in a state now.
  [[nodiscard]] std::size_t count(OrderState state) const;
  // Lead time (accepted → done) of the done orders at quantile q (0..1; nearest rank); zero
  // before the first.
  [[nodiscard]] std::chrono::nanoseconds lead_time(double q) const;
  // Boxes made again after their attempt failed.
  [[nodiscard]] std::uint64_t remade() const { return remade_; }
  [[nodiscard]] const std::map<std::string, OrderRecord>& records() const { return records_; }
  [[nodiscard]] std::size_t wip() const { return wip_; }
  // Products on the line now (admitted, not yet settled).
  [[nodiscard]] std::size_t active() const { return agents_.size(); }
  [[nodiscard]] bool idle() const { return queue_.empty() && agents_.empty(); }

 private:
  void admit(OrderRecord& record);
  void settle(const OrderAgent& agent);
  void emit(const std::string& order, std::string what, std::string detail);
  // Every state change goes through here: count() is asked every step of a long run.
  void set_state(OrderRecord& r, OrderState state);

  BeltBlocks belts_;
  ProductContext context_;
  OrderHostOptions options_;
  OrderEventSink sink_;
  std::size_t wip_;
  std::map<std::string, OrderRecord> records_;
  std::deque<std::string> queue_;
  std::vector<std::shared_ptr<OrderAgent>> agents_;
  std::uint64_t remade_ = 0;
  std::array<std::size_t, kOrderStates> counts_{};  // by OrderState
};

// The inspection of an "inspected" event of `record`'s order as the order service publishes it
// (OrderService.LastInspection, sf/line/inspection.hpp): the order, its box, what it asks for,
// what the downloader counted and the seconds since the order was accepted.
line::InspectionRecord inspection_record(const OrderEvent& inspected, const OrderRecord& record);

// The most boxes the layout's belts can hold without a circle of boxes
// waiting for one another: one less than the belts of its shortest cycle
// (every belt when the belts form no cycle).
std::size_t safe_wip(const line::Layout& layout);

}  // namespace sf::factory
