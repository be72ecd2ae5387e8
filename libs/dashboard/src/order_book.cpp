// OrderBook (order_book.hpp): an order's state follows from its steps, replayed in time order
// whenever one arrives, so a step delivered late (history replayed after live events) or twice
// (the same event stored and received) leaves the same view.
#include "sf/dashboard/order_book.hpp"

#include <algorithm>
#include <charconv>

#include "sf/core/text.hpp"
#include "sf/factory/order.hpp"

namespace sf::dashboard {

namespace {

// The order's state after a step (order_host.hpp's OrderState, and "submitted" before any).
std::optional<std::string_view> state_after(std::string_view what) {
  if (what == "accepted" || what == "remade") {
    return "queued";
  }
  if (what == "done" || what == "failed" || what == "cancelled") {
    return what;
  }
  if (what == "cancel-refused" || what == "retry") {
    return std::nullopt;
  }
  return "in work";  // started, awarded, routed, transported, uploaded, loaded, inspected, rejected, ...
}

// "small-box gummy:4,toffee:2": the accepted step's detail (OrderHost::submit).
void read_content(OrderView& o, std::string_view detail) {
  const auto space = detail.find(' ');
  if (space == std::string_view::npos) {
    return;
  }
  std::map<std::string, int> candy;
  for (std::string_view item : split(detail.substr(space + 1), ',')) {
    auto line = factory::parse_order_line(item);
    if (!line) {
      return;  // not the format we know: keep what the book had
    }
    candy[line->candy] += line->quantity;
  }
  o.box = std::string(detail.substr(0, space));
  o.candy = std::move(candy);
}

// "box 12 at conveyor1/upload" (uploaded), "box 12 conveyor1/upload → conveyor3/toshiba"
// (transported): the box number and the last place named.
std::optional<std::pair<int, std::string>> box_and_place(std::string_view detail) {
  const auto words = split(detail, ' ');
  if (words.size() < 3 || words[0] != "box") {
    return std::nullopt;
  }
  int number = 0;
  const auto digits = words[1];
  if (auto [end, ec] = std::from_chars(digits.data(), digits.data() + digits.size(), number);
      ec != std::errc{} || end != digits.data() + digits.size() || words.back().empty()) {
    return std::nullopt;
  }
  return std::pair{number, std::string(words.back())};
}

// "A -c1-> B -c2-> C (1.234 s)" (routed): the legs after A; nullopt if it does not read so.
std::optional<std::vector<RouteLeg>> route_legs(std::string_view detail) {
  if (const auto paren = detail.rfind(" ("); paren != std::string_view::npos) {
    detail = detail.substr(0, paren);
  }
  const auto words = split(detail, ' ');
  if (words.empty() || words.size() % 2 == 0) {
    return std::nullopt;
  }
  std::vector<RouteLeg> legs;
  for (std::size_t i = 1; i + 1 < words.size(); i += 2) {
    const auto arrow = words[i];
    if (arrow.size() < 4 || !arrow.starts_with('-') || !arrow.ends_with("->")) {
      return std::nullopt;
    }
    legs.push_back({std::string(arrow.substr(1, arrow.size() - 3)), std::string(words[i + 1])});
  }
  return legs;
}

// The box's place after a step of its order (the order's state already updated).
void move_box(OrderView& o, const line::OrderStep& step) {
  const std::string& what = step.what;
  if (what == "started" || o.state != "in work") {
    o.place.reset();  // a new box begins, or the order's box left the line
  } else if (what == "uploaded") {
    if (auto bp = box_and_place(step.detail)) {
      o.place = BoxPlace{bp->first, bp->second, {}};
    }
  } else if (!o.place) {
    return;
  } else if (what == "routed") {
    if (auto legs = route_legs(step.detail)) {
      o.place->route = std::move(*legs);
    }
  } else if (what == "transported") {
    if (auto bp = box_and_place(step.detail)) {
      auto& route = o.place->route;
      const auto reached =
          std::find_if(route.begin(), route.end(), [&](const RouteLeg& leg) { return leg.to == bp->second; });
      route.erase(route.begin(), reached == route.end() ? route.end() : std::next(reached));
      o.place->at = bp->second;
    }
  } else if (what == "retry") {
    o.place->route.clear();  // routed again from where it stands
  }
}

}  // namespace

bool OrderBook::is_order_step(const historian::Event& event) {
  // OrderModel's object: ns=<its namespace>;s=OrderService (the index differs per server).
  return event.source_node.ends_with(";s=OrderService") && !event.source_name.empty();
}

OrderView& OrderBook::order(const std::string& id) {
  auto [it, added] = orders_.try_emplace(id);
  if (added) {
    it->second.id = id;
  }
  return it->second;
}

std::optional<std::string> OrderBook::on_event(const historian::Event& event) {
  if (event.server == kDashboardServer) {
    if (event.source_name.empty()) {
      return std::nullopt;
    }
    std::lock_guard lock(mutex_);
    order(event.source_name).owner = event.message;
    return event.source_name;
  }
  if (!is_order_step(event)) {
    return std::nullopt;
  }
  auto step = line::parse_order_step(event.message);
  std::lock_guard lock(mutex_);
  if (!step) {
    ++rejected_;
    return std::nullopt;
  }
  OrderView& o = order(event.source_name);
  const OrderStepView view{event.time, std::move(*step)};
  const auto at = std::upper_bound(o.steps.begin(), o.steps.end(), view.time,
                                   [](historian::Timestamp t, const OrderStepView& s) { return t < s.time; });
  const bool seen = std::any_of(o.steps.begin(), at, [&](const OrderStepView& s) {
    return s.time == view.time && s.step == view.step;
  });
  if (seen) {
    return std::nullopt;
  }
  o.steps.insert(at, view);
  o.state = "submitted";
  o.attempts = 0;
  o.machines.clear();
  o.place.reset();
  for (const auto& s : o.steps) {
    apply(o, s);
  }
  o.updated = std::max(o.updated, view.time);
  return o.id;
}

void OrderBook::apply(OrderView& o, const OrderStepView& s) {
  const std::string& what = s.step.what;
  if (what == "accepted") {
    read_content(o, s.step.detail);
  }
  if (what == "started") {
    ++o.attempts;  // a box begins for it
  }
  if (auto next = state_after(what)) {
    o.state = std::string(*next);
  }
  if (!s.step.machine.empty() &&
      std::find(o.machines.begin(), o.machines.end(), s.step.machine) == o.machines.end()) {
    o.machines.push_back(s.step.machine);
  }
  move_box(o, s.step);
}

std::optional<std::string> OrderBook::on_inspection(std::string_view text, historian::Timestamp time) {
  auto record = line::parse_inspection(text);
  std::lock_guard lock(mutex_);
  if (!record) {
    if (!text.empty()) {
      ++rejected_;
    }
    return std::nullopt;
  }
  OrderView& o = order(record->order);
  if (o.box.empty()) {  // accepted before the gateway subscribed (its event never reached us)
    o.box = record->box_type;
    o.candy = record->ordered;
  }
  o.inspection = std::move(*record);
  o.updated = std::max(o.updated, time);
  return o.id;
}

void OrderBook::placed(const std::string& id, const std::string& owner, const std::string& box,
                       const std::map<std::string, int>& candy, historian::Timestamp time) {
  std::lock_guard lock(mutex_);
  OrderView& o = order(id);
  o.owner = owner;
  if (o.box.empty()) {
    o.box = box;
    o.candy = candy;
  }
  o.updated = std::max(o.updated, time);
}

std::optional<OrderView> OrderBook::find(const std::string& id) const {
  std::lock_guard lock(mutex_);
  const auto it = orders_.find(id);
  return it == orders_.end() ? std::nullopt : std::optional(it->second);
}

std::vector<OrderView> OrderBook::list(const std::optional<std::string>& owner,
                                       const std::optional<std::string>& state, std::size_t limit) const {
  std::vector<OrderView> out;
  {
    std::lock_guard lock(mutex_);
    for (const auto& [id, o] : orders_) {
      if ((!owner || o.owner == *owner) && (!state || o.state == *state)) {
        out.push_back(o);
      }
    }
  }
  std::stable_sort(out.begin(), out.end(),
                   [](const OrderView& a, const OrderView& b) { return a.updated > b.updated; });
  if (out.size() > limit) {
    out.resize(limit);
  }
  return out;
}

std::size_t OrderBook::size() const {
  std::lock_guard lock(mutex_);
  return orders_.size();
}

std::uint64_t OrderBook::rejected() const {
  std::lock_guard lock(mutex_);
  return rejected_;
}

}  // namespace sf::dashboard
