#include "sf/negotiation/product.hpp"

#include <algorithm>

#include <fmt/format.h>

namespace sf::negotiation {

Product::Product(Manager& manager, RoutePlanner* planner, ProductPlan plan, ProductEvents events)
    : manager_(&manager), planner_(planner), plan_(std::move(plan)), events_(std::move(events)) {
  location_ = plan_.start;
}

Status Product::start() {
  if (started_) {
    return Error{Errc::state, fmt::format("product {} already started", plan_.name)};
  }
  SF_TRY(validate_name("product", plan_.name));
  SF_TRY(validate_location(plan_.start));
  for (const auto& op : plan_.operations) {
    SF_TRY(validate_operation(op));
  }
  if (plan_.route && planner_ == nullptr) {
    return Error{Errc::invalid_argument,
                 fmt::format("product {} routes but has no route planner", plan_.name)};
  }
  started_ = true;
  begin_step();
  return {};
}

void Product::begin_step() {
  if (index_ >= plan_.operations.size()) {
    finish({});
    return;
  }
  const auto& op = plan_.operations[index_];
  current_ = Step{op, {}, {}, 0, 0, std::chrono::nanoseconds{0}, std::nullopt, {}, {}};
  work_done_ = false;
  route_done_ = !plan_.route;
  OperationRequest request{plan_.name, op, params_of(op), {}};
  if (auto it = plan_.directed.find(op); it != plan_.directed.end()) {
    request.directed_to = it->second;
  }
  ConversationEvents ev{
      [this](const Conversation& c) { on_confirmed(c); }, [this](const Conversation& c) { on_done(c); },
      [this](const Conversation& c) { finish(fmt::format("{}: {}", c.operation, c.failure)); }};
  auto id = manager_->negotiate(std::move(request), std::move(ev));
  if (!id) {
    finish(id.error().describe());
    return;
  }
  current_.conversation = *id;
}

std::vector<Param> Product::params_of(const std::string& operation) const {
  std::vector<Param> out;
  if (auto it = plan_.params.find(operation); it != plan_.params.end()) {
    out = it->second;
  }
  for (const Param& p : carried_) {
    if (std::none_of(out.begin(), out.end(), [&](const Param& q) { return q.name == p.name; })) {
      out.push_back(p);
    }
  }
  return out;
}

void Product::on_confirmed(const Conversation& c) {
  current_.contractor = c.contractor;
  current_.round = c.round;
  current_.renegotiations = c.renegotiations;
  current_.negotiation_time = c.confirmed_at - c.started_at;
  if (events_.on_award) {
    events_.on_award(plan_.name, c);
  }
  if (!plan_.route) {
    return;
  }
  // A renegotiation may change the machine: plan (again) towards the new one.
  route_done_ = false;
  const auto token = ++route_token_;
  auto id = planner_->plan(plan_.name, location_, c.contractor,
                           [this, token](const Result<Route>& r) { on_route(token, r); });
  if (!id) {
    finish(id.error().describe());
  }
}

void Product::on_route(std::uint64_t token, const Result<Route>& route) {
  if (token != route_token_ || finished_) {
    return;  // superseded by a renegotiation
  }
  if (!route) {
    finish(route.error().describe());
    return;
  }
  current_.route = *route;
  route_done_ = true;
  if (events_.on_route) {
    events_.on_route(plan_.name, *route);
  }
  maybe_complete_step();
}

void Product::on_done(const Conversation& c) {
  current_.contractor = c.contractor;
  current_.result = c.result;
  current_.results = c.results;
  for (const Param& r : c.results) {
    if (std::find(plan_.carry.begin(), plan_.carry.end(), r.name) == plan_.carry.end()) {
      continue;
    }
    std::erase_if(carried_, [&](const Param& p) { return p.name == r.name; });
    carried_.push_back(r);
  }
  work_done_ = true;
  maybe_complete_step();
}

void Product::maybe_complete_step() {
  if (!work_done_ || !route_done_ || finished_) {
    return;
  }
  location_ = current_.contractor;
  steps_.push_back(current_);
  if (events_.on_step_done) {
    events_.on_step_done(plan_.name, steps_.back());
  }
  ++index_;
  begin_step();
}

void Product::finish(std::string failure) {
  if (finished_) {
    return;
  }
  finished_ = true;
  failure_ = std::move(failure);
  if (events_.on_finished) {
    events_.on_finished(plan_.name, failure_.empty(), failure_);
  }
}

}  // namespace sf::negotiation
