// TimedDecisions: how long products wait for decisions (an operation until its
// machine is confirmed, a route until it is composed), around whoever decides.
// The negotiation share of lead time the scheduling benchmark reports.
#pragma once

#include <chrono>
#include <memory>
#include <string>

#include "sf/core/clock.hpp"
#include "sf/factory/order_agent.hpp"

namespace sf::simulation {

class TimedDecisions final : public factory::ProductDecisions {
 public:
  TimedDecisions(factory::ProductDecisions& inner, const Clock& clock) : inner_(&inner), clock_(&clock) {}

  Result<std::string> negotiate(negotiation::OperationRequest request,
                                negotiation::ConversationEvents events) override {
    // The first confirmation ends the wait (a renegotiation's waits are the product's too, but
    // they overlap its box's work and are left out).
    auto waiting = std::make_shared<bool>(true);
    auto stop = [this, waiting, since = clock_->now()] {
      if (*waiting) {
        *waiting = false;
        waited_ += clock_->now() - since;
      }
    };
    events.on_confirmed = [stop, f = std::move(events.on_confirmed)](const negotiation::Conversation& c) {
      stop();
      if (f) {
        f(c);
      }
    };
    events.on_failed = [stop, f = std::move(events.on_failed)](const negotiation::Conversation& c) {
      stop();
      if (f) {
        f(c);
      }
    };
    return inner_->negotiate(std::move(request), std::move(events));
  }

  Result<std::string> plan(const std::string& product, const std::string& from, const std::string& to,
                           negotiation::RouteCallback done) override {
    return inner_->plan(
        product, from, to,
        [this, since = clock_->now(), done = std::move(done)](const Result<negotiation::Route>& r) {
          waited_ += clock_->now() - since;
          done(r);
        });
  }

  // Summed over every product and decision.
  [[nodiscard]] std::chrono::nanoseconds waited() const { return waited_; }

 private:
  factory::ProductDecisions* inner_;
  const Clock* clock_;
  std::chrono::nanoseconds waited_{0};
};

}  // namespace sf::simulation
