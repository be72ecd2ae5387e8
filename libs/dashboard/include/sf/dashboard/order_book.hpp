// The order book (paper §VII: consumers follow their personalised boxes): every order the
// order service accepted, rebuilt from its OPC UA events as the gateway delivers and the
// historian keeps them (OrderModel::raise: SourceName the order, Message the step), with the
// inspection of its last box (OrderService.LastInspection) and the user who placed it.
//
// The book holds no state of its own that the historian does not: after a restart it is
// rebuilt by replaying the stored events (replay()). Thread-safe.
#pragma once

#include <cstddef>
#include <map>
#include <mutex>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "sf/historian/types.hpp"
#include "sf/line/inspection.hpp"

namespace sf::dashboard {

struct OrderStepView {
  historian::Timestamp time{};
  line::OrderStep step;
};

// Where an order's box is, as its steps tell (the operator's schematic draws it): the place
// ("belt/station", or a belt's name: where it takes boxes over) it was put or brought to last and the legs of
// its route not yet travelled, the first of them the conveyor that carries it next. From "uploaded" ("box N
// at P"), "routed" (Route::describe: "A -c1-> B -c2-> C (t s)") and "transported" ("box N A → B").
struct RouteLeg {
  std::string conveyor;
  std::string to;
  friend bool operator==(const RouteLeg&, const RouteLeg&) = default;
};
struct BoxPlace {
  int box = 0;
  std::string at;
  std::vector<RouteLeg> route;
};

struct OrderView {
  std::string id;
  std::string owner;  // who placed it through the API; empty for orders from a file
  std::string box;
  std::map<std::string, int> candy;  // as ordered
  // submitted (placed here, not yet seen accepted), queued, in work, done, failed, cancelled
  std::string state = "submitted";
  int attempts = 0;                   // boxes started for it
  std::vector<std::string> machines;  // that worked on it, first time first
  std::optional<line::InspectionRecord> inspection;
  std::optional<BoxPlace> place;  // while in work, once its box is on the line
  std::vector<OrderStepView> steps;
  historian::Timestamp updated{};
};

// The historian server name of the owner records the dashboard writes (one event per order
// placed through the API: SourceName the order, Message the user).
inline constexpr std::string_view kDashboardServer = "dashboard";

class OrderBook {
 public:
  // An event of any server: an order step when its SourceNode is the order service's object
  // (OrderModel); an owner record when its server is kDashboardServer. The id of the order it
  // changed, if any. Malformed steps are counted (rejected()) and otherwise ignored.
  std::optional<std::string> on_event(const historian::Event& event);
  // OrderService.LastInspection's text; the order it concerns, if it is one of the book's.
  std::optional<std::string> on_inspection(std::string_view text, historian::Timestamp time);
  // An order placed through the API, before the order service's "accepted" arrives.
  void placed(const std::string& id, const std::string& owner, const std::string& box,
              const std::map<std::string, int>& candy, historian::Timestamp time);

  [[nodiscard]] std::optional<OrderView> find(const std::string& id) const;
  // Newest first (by last update); `owner` set: that user's only; `state` set: that state only.
  [[nodiscard]] std::vector<OrderView> list(const std::optional<std::string>& owner,
                                            const std::optional<std::string>& state, std::size_t limit) const;
  [[nodiscard]] std::size_t size() const;
  [[nodiscard]] std::uint64_t rejected() const;

  // Does this event's source name the order service's object (an order step)?
  static bool is_order_step(const historian::Event& event);

 private:
  OrderView& order(const std::string& id);
  void apply(OrderView& o, const OrderStepView& step);

  mutable std::mutex mutex_;
  std::map<std::string, OrderView> orders_;
  std::uint64_t rejected_ = 0;
};

}  // namespace sf::dashboard
