#include "sf/factory/order_host.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include <fmt/format.h>
#include <fmt/ranges.h>

namespace sf::factory {

std::string_view to_string(OrderState s) {
  switch (s) {
    case OrderState::queued:
      return "queued";
    case OrderState::in_work:
      return "in work";
    case OrderState::done:
      return "done";
    case OrderState::failed:
      return "failed";
    case OrderState::cancelled:
      return "cancelled";
  }
  return "?";
}

std::size_t safe_wip(const line::Layout& layout) {
  // Breadth-first from each belt back to itself: the shortest cycle through it.
  const std::size_t n = layout.belts.size();
  std::size_t shortest = std::numeric_limits<std::size_t>::max();
  for (std::size_t start = 0; start < n; ++start) {
    std::vector<std::size_t> depth(n, 0);
    std::vector<std::size_t> frontier{start};
    for (std::size_t d = 1; !frontier.empty() && d < shortest; ++d) {
      std::vector<std::size_t> next;
      for (std::size_t b : frontier) {
        for (const auto& name : layout.belts[b].next) {
          const std::size_t to = *layout.belt_index(name);
          if (to == start) {
            shortest = std::min(shortest, d);
          } else if (depth[to] == 0) {
            depth[to] = d;
            next.push_back(to);
          }
        }
      }
      frontier = std::move(next);
    }
  }
  if (shortest == std::numeric_limits<std::size_t>::max()) {
    return std::max<std::size_t>(1, n);
  }
  return std::max<std::size_t>(1, shortest - 1);
}

OrderHost::OrderHost(const ProductContext& context, OrderHostOptions options, OrderEventSink sink)
    : context_(context),
      options_(options),
      sink_(std::move(sink)),
      wip_(options.wip == 0 ? safe_wip(*context.layout) : options.wip) {
  if (context_.belts == nullptr) {
    context_.belts = &belts_;
  }
}

Status OrderHost::submit(Order order) {
  if (order.id.empty()) {
    return make_error(Errc::invalid_argument, "an order needs an id");
  }
  if (records_.contains(order.id)) {
    return make_error(Errc::invalid_argument, fmt::format("order '{}' was accepted before", order.id));
  }
  if (auto valid = validate(order, context_.layout->catalog); !valid) {
    return make_error(Errc::invalid_argument, fmt::format("order '{}': {}", order.id, valid.error().message));
  }
  const std::string id = order.id;
  OrderRecord& r = records_[id];
  r.order = std::move(order);
  r.accepted = context_.clock->now();
  ++counts_[static_cast<std::size_t>(OrderState::queued)];
  queue_.push_back(id);
  // The detail carries the whole order ("small-box gummy:4,toffee:2"): a client that sees only
  // the events (the cloud's order book) knows what was ordered.
  std::vector<std::string> lines;
  for (const auto& l : r.order.lines) {
    lines.push_back(fmt::format("{}:{}", l.candy, l.quantity));
  }
  emit(id, "accepted", fmt::format("{} {}", r.order.box_type, fmt::join(lines, ",")));
  return {};
}

Status OrderHost::cancel(const std::string& id) {
  const auto found = records_.find(id);
  if (found == records_.end()) {
    return make_error(Errc::not_found, fmt::format("no order '{}'", id));
  }
  OrderRecord& r = found->second;
  const auto queued = std::find(queue_.begin(), queue_.end(), id);
  if (r.state != OrderState::queued || queued == queue_.end()) {
    return make_error(Errc::state, fmt::format("order '{}' is {}", id, to_string(r.state)));
  }
  queue_.erase(queued);
  set_state(r, OrderState::cancelled);
  r.finished = context_.clock->now();
  emit(id, "cancelled", "withdrawn before a box was started");
  return {};
}

void OrderHost::tick() {
  while (!queue_.empty() && agents_.size() < wip_) {
    OrderRecord& r = records_.at(queue_.front());
    queue_.pop_front();
    admit(r);
  }
  for (std::size_t i = 0; i < agents_.size();) {
    agents_[i]->tick();
    if (agents_[i]->finished()) {
      const auto agent = agents_[i];
      agents_.erase(agents_.begin() + static_cast<std::ptrdiff_t>(i));
      settle(*agent);
    } else {
      ++i;
    }
  }
}

void OrderHost::admit(OrderRecord& r) {
  ++r.attempts;
  set_state(r, OrderState::in_work);
  emit(r.order.id, "started", fmt::format("attempt {}", r.attempts));
  auto agent = OrderAgent::create(r.order, fmt::format("{}.{}", r.order.id, r.attempts), context_,
                                  options_.agent, sink_);
  agents_.push_back(agent);
  if (auto started = agent->start(); !started) {
    r.failure = started.error().describe();
  }
}

void OrderHost::settle(const OrderAgent& agent) {
  OrderRecord& r = records_.at(agent.order().id);
  if (agent.box() != 0) {
    r.boxes.push_back(agent.box());
  }
  r.inspection = agent.inspection();
  r.failure = agent.failure();
  if (agent.ok()) {
    set_state(r, OrderState::done);
    r.finished = context_.clock->now();
    return;
  }
  if (r.attempts < options_.max_attempts) {
    set_state(r, OrderState::queued);
    queue_.push_front(r.order.id);
    ++remade_;
    emit(r.order.id, "remade", fmt::format("attempt {} failed: {}", r.attempts, r.failure));
    return;
  }
  set_state(r, OrderState::failed);
  r.finished = context_.clock->now();
}

line::InspectionRecord inspection_record(const OrderEvent& inspected, const OrderRecord& record) {
  line::InspectionRecord r;
  r.order = inspected.order;
  r.box_type = record.order.box_type;
  r.ordered = record.order.counts();
  r.lead_s = std::chrono::duration<double>(inspected.at - record.accepted).count();
  if (inspected.inspection) {
    r.box = inspected.inspection->box;
    r.counted = inspected.inspection->counts;
    r.weight_g = inspected.inspection->weight_g;
  }
  return r;
}

std::chrono::nanoseconds OrderHost::lead_time(double q) const {
  std::vector<std::chrono::nanoseconds> leads;
  for (const auto& [id, r] : records_) {
    if (r.state == OrderState::done) {
      leads.push_back(r.finished - r.accepted);
    }
  }
  if (leads.empty()) {
    return {};
  }
  const auto i =
      static_cast<std::size_t>(std::lround(std::clamp(q, 0.0, 1.0) * static_cast<double>(leads.size() - 1)));
  std::nth_element(leads.begin(), leads.begin() + static_cast<std::ptrdiff_t>(i), leads.end());
  return leads[i];
}

std::size_t OrderHost::count(OrderState state) const {
  return counts_[static_cast<std::size_t>(state)];
}

void OrderHost::set_state(OrderRecord& r, OrderState state) {
  --counts_[static_cast<std::size_t>(r.state)];
  ++counts_[static_cast<std::size_t>(state)];
  r.state = state;
}

void OrderHost::emit(const std::string& order, std::string what, std::string detail) {
  if (sink_) {
    sink_({context_.clock->now(), order, std::move(what), {}, std::move(detail), std::nullopt});
  }
}

}  // namespace sf::factory
