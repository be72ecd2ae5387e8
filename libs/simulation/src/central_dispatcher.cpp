#include "sf/simulation/central_dispatcher.hpp"

#include <algorithm>
#include <tuple>

#include <fmt/format.h>

#include "sf/factory/contract_net.hpp"
#include "sf/negotiation/route.hpp"

namespace sf::simulation {

namespace cnp = sf::negotiation;

CentralDispatcher::CentralDispatcher(const Clock& clock, DispatcherOptions options)
    : clock_(&clock), options_(options) {}

void CentralDispatcher::add(factory::MachineController& machine,
                            std::function<factory::ConveyorOffer()> offer) {
  machine.on_job_end([this](const factory::JobOutcome& outcome) { ended_.push_back(outcome); });
  machines_[machine.identification().name] = Machine{&machine, machine.operations(), std::move(offer)};
}

Result<std::string> CentralDispatcher::negotiate(cnp::OperationRequest request,
                                                 cnp::ConversationEvents events) {
  const std::string id = fmt::format("dispatch-{}", ++next_id_);
  if (!request.directed_to.empty()) {
    directed_[id] = request.directed_to;
  }
  jobs_.emplace(id, cnp::open_conversation(id, std::move(request), std::move(events), clock_->now()));
  due_.emplace(clock_->now(), id);
  return id;
}

Result<std::string> CentralDispatcher::plan(const std::string& /*product*/, const std::string& from,
                                            const std::string& to, cnp::RouteCallback done) {
  routes_.push_back({from, to, std::move(done)});
  return fmt::format("route-{}", ++next_id_);
}

void CentralDispatcher::tick() {
  const auto now = clock_->now();
  while (!due_.empty() && due_.begin()->first <= now) {
    const std::string id = due_.begin()->second;
    due_.erase(due_.begin());
    decide(id);
  }
  while (!routes_.empty()) {
    RouteAsk ask = std::move(routes_.front());
    routes_.pop_front();
    route(ask);
  }
  while (!ended_.empty()) {
    const factory::JobOutcome outcome = std::move(ended_.front());
    ended_.pop_front();
    on_job_end(outcome);
  }
}

std::string CentralDispatcher::earliest_finish(const cnp::Conversation& c, const std::string& directed_to,
                                               std::string& why_not) {
  const factory::Operation op = factory::to_operation(c.operation, c.params);
  std::string best;
  std::tuple<std::chrono::nanoseconds, std::chrono::nanoseconds> best_key{};
  for (const auto& [name, m] : machines_) {
    if ((!directed_to.empty() && name != directed_to) ||
        std::find(m.operations.begin(), m.operations.end(), c.operation) == m.operations.end()) {
      continue;
    }
    ++stats_.estimates;
    std::string why;
    const auto e = m.controller->estimate(op, &why);
    if (!e) {
      why_not = fmt::format("{}: {}", name, why);
      continue;
    }
    const auto key = std::make_tuple(e->start_in + e->duration, e->duration);
    if (best.empty() || key < best_key) {
      best = name;
      best_key = key;
    }
  }
  return best;
}

void CentralDispatcher::decide(const std::string& id) {
  auto it = jobs_.find(id);
  if (it == jobs_.end()) {
    return;
  }
  cnp::Conversation& c = it->second;
  ++c.round;
  const auto directed = directed_.find(id);
  std::string why_not = "no machine can do it";
  const std::string machine =
      earliest_finish(c, directed == directed_.end() ? std::string{} : directed->second, why_not);
  if (!machine.empty()) {
    auto st = machines_.at(machine).controller->submit(id, factory::to_operation(c.operation, c.params));
    if (st) {
      ++stats_.assigned;
      c.contractor = machine;
      c.phase = cnp::Phase::Working;
      c.confirmed_at = clock_->now();
      if (c.events.on_confirmed) {
        c.events.on_confirmed(c);
      }
      return;
    }
    why_not = st.error().message;
  }
  if (c.round < options_.max_rounds) {
    due_.emplace(clock_->now() + options_.retry_delay, id);
    return;
  }
  ++stats_.failed;
  cnp::Conversation failed = std::move(c);
  jobs_.erase(it);
  directed_.erase(id);
  failed.phase = cnp::Phase::Failed;
  failed.failure = fmt::format("no machine took it in {} rounds: {}", failed.round, why_not);
  if (failed.events.on_failed) {
    failed.events.on_failed(failed);
  }
}

void CentralDispatcher::on_job_end(const factory::JobOutcome& outcome) {
  auto it = jobs_.find(outcome.job);
  if (it == jobs_.end()) {
    return;
  }
  if (!outcome.ok) {
    // As the manager does with a FAILURE: the operation is assigned again (renegotiation),
    // within the same bound on rounds.
    ++it->second.renegotiations;
    it->second.contractor.clear();
    due_.emplace(clock_->now(), outcome.job);
    return;
  }
  cnp::Conversation done = std::move(it->second);
  jobs_.erase(it);
  directed_.erase(outcome.job);
  done.phase = cnp::Phase::Done;
  done.result = outcome.detail;
  done.results = factory::to_params(outcome.results);
  if (done.events.on_done) {
    done.events.on_done(done);
  }
}

void CentralDispatcher::route(RouteAsk& ask) {
  ++stats_.routes;
  std::vector<cnp::Segment> segments;
  for (const auto& [name, m] : machines_) {
    if (!m.offer) {
      continue;
    }
    const factory::ConveyorOffer offer = m.offer();
    if (offer.unavailable) {
      continue;
    }
    for (const auto& s : offer.segments) {
      segments.push_back({name, s.from, s.to, s.transit_time});
    }
  }
  if (auto r = cnp::shortest_route(segments, ask.from, ask.to)) {
    return ask.done(*r);
  }
  ask.done(make_error(Errc::not_found, fmt::format("no conveyor route from {} to {}", ask.from, ask.to)));
}

}  // namespace sf::simulation
